// The photo passes' prefetching reader (bake/photo/photo_view.h) and the
// BackgroundTask under it (bake/util/parallel.h): each photo's image is the
// one its reader gives for it, the reader's calls stay one at a time and in
// the photos' order, a photo asked for out of order is still its own, and
// errors reach the caller of the photo they belong to.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "bake/photo/photo_view.h"
#include "bake/util/parallel.h"

namespace texbake {
namespace {

CameraProjector camera() {
  Expected<CameraPose> pose = pose_from_look_at({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, "test");
  EXPECT_TRUE(pose);
  return CameraProjector::make({CameraModel::kPinhole, 4, 3, {4, 4, 2, 1.5}, *pose}).value();
}

std::vector<Photo> photos(int n) {
  std::vector<Photo> out;
  for (int i = 0; i < n; ++i) {
    out.push_back({"p" + std::to_string(i), camera(), "p" + std::to_string(i) + ".png", {}});
  }
  return out;
}

// A reader that records its calls, fails for "p3", takes a while (so that a
// second call, if any overlapped, would be seen) and gives a 1 x 1 image
// whose red value is the photo's number.
struct Recorder {
  std::vector<std::string> calls;
  std::atomic<int> in_flight{0};
  std::atomic<int> most_in_flight{0};
  PhotoReader reader() {
    return [this](const Photo& photo) -> Expected<PhotoImage> {
      const int now = ++in_flight;
      int most = most_in_flight.load();
      while (now > most && !most_in_flight.compare_exchange_weak(most, now)) {
      }
      calls.push_back(photo.name);
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      --in_flight;
      if (photo.name == "p3") return make_error(ErrorCode::kIo, "p3.png: cannot open");
      const float k = static_cast<float>(std::stoi(photo.name.substr(1)));
      return PhotoImage{1, 1, {k, 0, 0, 1}, ColorSpace::kLinear};
    };
  }
};

TEST(PrefetchingReader, GivesEachPhotoItsOwnImageWithCallsInOrderOneAtATime) {
  const std::vector<Photo> list = photos(6);
  Recorder rec;
  {
    const PhotoReader read = photo_detail::prefetching_reader(rec.reader(), list);
    for (int i = 0; i < 6; ++i) {
      // The work on photo i, while photo i + 1 is read.
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
      Expected<PhotoImage> image = read(list[i]);
      if (i == 3) {
        ASSERT_FALSE(image);
        EXPECT_EQ(image.error().message, "p3.png: cannot open");
        continue;
      }
      ASSERT_TRUE(image) << image.error().message;
      EXPECT_EQ(image->pixels[0], static_cast<float>(i));
    }
  }
  EXPECT_EQ(rec.calls, (std::vector<std::string>{"p0", "p1", "p2", "p3", "p4", "p5"}));
  EXPECT_EQ(rec.most_in_flight.load(), 1);
}

TEST(PrefetchingReader, APhotoAskedForOutOfOrderIsStillItsOwn) {
  const std::vector<Photo> list = photos(5);
  Recorder rec;
  const PhotoReader read = photo_detail::prefetching_reader(rec.reader(), list);
  // p0 (then p1 read ahead), p4 (p1 dropped, p4 read), p2 (p2 read again).
  for (int i : {0, 4, 2}) {
    Expected<PhotoImage> image = read(list[i]);
    ASSERT_TRUE(image);
    EXPECT_EQ(image->pixels[0], static_cast<float>(i));
  }
  // A photo of another list (a copy): read directly.
  const Photo copy = list[1];
  Expected<PhotoImage> image = read(copy);
  ASSERT_TRUE(image);
  EXPECT_EQ(image->pixels[0], 1.0f);
  EXPECT_EQ(rec.most_in_flight.load(), 1);
}

// A pass that stops early (an error) drops the reader with the next photo's
// read running: the reader waits for it, and its image is freed (the
// sanitizer stage's LeakSanitizer sees it otherwise).
TEST(PrefetchingReader, AReaderDroppedWithAReadRunningWaitsForIt) {
  const std::vector<Photo> list = photos(3);
  Recorder rec;
  {
    const PhotoReader read = photo_detail::prefetching_reader(rec.reader(), list);
    ASSERT_TRUE(read(list[0]));
  }
  EXPECT_EQ(rec.calls, (std::vector<std::string>{"p0", "p1"}));
  EXPECT_EQ(rec.in_flight.load(), 0);
}

TEST(BackgroundTask, RunsBesideTheCallerAndWaitReturnsAfterIt) {
  std::atomic<int> done{0};
  {
    BackgroundTask task;
    task.wait();  // nothing started: returns at once
    task.run([&] { done = 1; });
    task.wait();
    EXPECT_EQ(done.load(), 1);
    task.run([&] {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      done = 2;
    });
  }  // the destructor waits
  EXPECT_EQ(done.load(), 2);
  // One thread: the task runs when waited for, and still runs.
  int value = 0;
  run_in_arena(1, [&] {
    BackgroundTask task;
    task.run([&] { value = 7; });
    task.wait();
  });
  EXPECT_EQ(value, 7);
}

}  // namespace
}  // namespace texbake
