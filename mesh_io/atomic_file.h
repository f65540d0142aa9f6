// Atomic output files (SPEC section 8): each output is written to a
// temporary file in its target's folder and renamed over the target only
// when complete, so no partial file ever appears under a target's name, and
// a set of files (an OBJ with its MTL and atlas image) changes together.
//
// Temporaries are hidden files named
//   .texbake-<host>-<pid>-<n>-<random><ext>
// (<host> a short hash of the host name, <ext> the target's extension when
// it is short, else ".tmp": extension-sniffing writers such as OpenImageIO
// pick the format from it). The name's length does not depend on the
// target's, so a temporary fits wherever the target's name fits.
//  - A failure, an exception or a caught SIGINT/SIGTERM/SIGHUP (see
//    install_signal_cleanup) removes the temporaries.
//  - A SIGKILL cannot be caught: the next texbake that writes into the same
//    folder removes the temporaries of processes of this host that no longer
//    run, and completes their interrupted commits (below).
//
// Targets:
//  - A symbolic link is written through: its final target is replaced, the
//    link stays.
//  - An existing regular file must be writable (write permission for the
//    caller, and not read-only by its mode bits, even for root): else kIo
//    "is read-only". The new file keeps the old one's permission bits.
//  - A character device (/dev/null, a terminal) or a FIFO with a reader is
//    written directly (no temporary, no rename): such a target is never
//    replaced by a regular file. A FIFO without a reader, a block device, a
//    socket or a folder is an error.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "mapping/error.h"

namespace texbake {

using WriteFunction = std::function<Status(const std::filesystem::path& temp)>;

// A set of output files replaced all together or not at all. stage() writes
// each file to its temporary; commit() renames them over their targets in
// staging order after writing a journal of the renames to the first
// target's folder, with SIGINT/SIGTERM/SIGHUP blocked: if the process is
// killed among the renames, the next texbake writing into that folder
// completes them from the journal, so readers see the old set or the new one
// (a reader opening files during the microseconds of the renames may see
// both). A set destroyed without commit() removes its temporaries.
class AtomicFileSet {
 public:
  AtomicFileSet();
  ~AtomicFileSet();
  AtomicFileSet(const AtomicFileSet&) = delete;
  AtomicFileSet& operator=(const AtomicFileSet&) = delete;

  // Calls write(temp) with a fresh temporary path for `target` (or the
  // target itself for a device or FIFO, see above). Errors (naming the
  // target): check_writable's, write's own (the temporary is removed), an
  // exception from write (kIo with its message).
  Status stage(const std::filesystem::path& target, const WriteFunction& write);

  // Removes `target` with the commit, before the renames (journalled with
  // them): a file of an older set that must not outlive the new one (a
  // COLMAP model's other form). Nothing to do when it does not exist (a
  // symbolic link is removed itself). Errors (kIo naming the target, before
  // anything changes): a folder, a folder that is not writable.
  Status stage_removal(const std::filesystem::path& target);

  // Removes the staged removals, then renames every staged temporary over
  // its target. Errors: kIo naming the target whose removal or rename
  // failed (targets removed or renamed before it keep their new state; the
  // rest keep their old one, and the temporaries are removed).
  Status commit();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One file: AtomicFileSet with a single stage() and commit().
Status write_atomically(const std::filesystem::path& target, const WriteFunction& write);

// set->stage(target, write) when `set` is given (the caller commits the
// set), else write_atomically(target, write): for writers that can be part
// of a set (image_io.h, write_mesh.h: their options' file_set).
Status stage_or_write(AtomicFileSet* set, const std::filesystem::path& target,
                      const WriteFunction& write);

// Checks, before any long work, that `target` can be written as described
// above: its folder exists and is writable, and the target is not a folder,
// a read-only file, a FIFO without a reader or another kind of special file.
// Errors: kIo naming the target.
Status check_writable(const std::filesystem::path& target);

// True when both paths name the same existing file (device and inode, after
// following links): an output that would overwrite an input.
bool same_file(const std::filesystem::path& a, const std::filesystem::path& b);

// Installs handlers for SIGINT, SIGTERM and SIGHUP that remove the
// temporaries of the writes in progress and then end the process by the
// same signal (the shell sees 128 + signal). For programs (the texbake
// executable calls it at start-up); a library never installs handlers by
// itself. Idempotent.
void install_signal_cleanup();

// Test hook: when set, called by AtomicFileSet::commit after the rename of
// staged file `index` (0-based), so a test can kill the process there.
extern void (*g_after_commit_rename_for_tests)(std::size_t index);

// The temporaries (and commit journals) texbake would leave for `folder`'s
// targets: the names that start with ".texbake-". For tests.
std::vector<std::filesystem::path> list_texbake_temporaries(const std::filesystem::path& folder);

}  // namespace texbake
