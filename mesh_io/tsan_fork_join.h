// ThreadSanitizer and oneTBB. Debian's libtbb is not built with TSan, so the
// hand-over of a parallel loop's tasks between threads, which happens inside
// libtbb, is invisible to it: it would report the caller's writes before a
// loop, read by the loop's bodies, and the bodies' writes, read by the caller
// after the loop, as races. ForkJoin marks exactly those two edges, and
// nothing else:
//   ForkJoin fork_join;                       // the fork, on the caller
//   tbb::parallel_for(..., [&](...) {
//     fork_join.begin_body();  ...work...  fork_join.end_body();
//   });
//   fork_join.join();                         // the join, on the caller
// Two bodies stay unordered, so a race between them (two chunks writing one
// element) is still reported. Compiled to nothing without -fsanitize=thread.
// oneTBB's own header code is covered by tests/tsan.supp (scripts/test.sh's
// tsan stage).
#pragma once

#if defined(__SANITIZE_THREAD__)
#define TEXBAKE_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define TEXBAKE_TSAN 1
#endif
#endif

#ifdef TEXBAKE_TSAN
extern "C" void __tsan_acquire(void* addr);
extern "C" void __tsan_release(void* addr);
#endif

namespace texbake {

class ForkJoin {
 public:
  // The fork: everything the calling thread did so far happens before every
  // body that calls begin_body().
  ForkJoin() { release(&fork_); }
  ForkJoin(const ForkJoin&) = delete;
  ForkJoin& operator=(const ForkJoin&) = delete;

  // The fork again, for an object that hands over more than once (a
  // background task run again after its wait()).
  void fork() { release(&fork_); }

  void begin_body() { acquire(&fork_); }
  void end_body() { release(&join_); }
  // The join: every body that called end_body() happens before what the
  // calling thread does next.
  void join() { acquire(&join_); }

 private:
#ifdef TEXBAKE_TSAN
  static void acquire(void* address) {
    __tsan_acquire(address);
  }
  static void release(void* address) {
    __tsan_release(address);
  }
#else
  static void acquire(void*) {}
  static void release(void*) {}
#endif
  char fork_ = 0;
  char join_ = 0;
};

}  // namespace texbake
