#pragma once
// How every mvox writer creates a file: all or nothing, never a half-written target, never a
// replaced link or device.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "write/buffered_writer.h"

namespace mvox {

// A file being written. For a regular target the bytes go to a temporary file in the target's
// directory (".NAME.XXXXXX", the name shortened when NAME is too long to take the suffix), and
// publishing moves it onto the target in one rename, so readers see either the previous file or
// the complete new one. If it is never published (an error, an exception, an early return) the
// destructor deletes the temporary and the target is left as it was.
//
// A target that is a symbolic link is written through it: the file the link leads to is
// replaced (created, if the link dangles) and the link stays, as a shell's `>` would do.
//
// Targets that are not regular files are written directly, because renaming onto them would
// replace them: "-" means standard output; /dev/stdout, /dev/stderr, /dev/fd/N and
// /proc/self/fd/N mean that descriptor, whatever file the shell put behind it; anything else
// under /dev or /proc, and any existing device, pipe or socket, is opened for writing, never
// created or renamed over. Such outputs cannot be overwritten later (can_overwrite() is false)
// and are not atomic. A standard output that was closed when mvox started is refused
// (standard_descriptors.h), so that nothing is written into a file that took its number.
//
// From creation to publishing or destruction the output is recorded as in progress
// (termination.h), so that an interrupt deletes the temporary and names the output.
//
// Every failure (cannot create, write, sync, close or rename) throws mvox::Error whose subject is
// the target path ("standard output" for "-"), e.g. "out/mesh.ply: write failed: No space left on
// device". Writes are buffered (BufferedWriter::kBufferBytes), so a full disk may only be
// reported by a later write() or by commit(). After an error the file is dead: commit() throws.
class OutputFile {
 public:
  // Creates the temporary (or opens the direct target). Throws mvox::Error.
  // `sync`: make the file durable (fsync) before it is renamed into place, so that a power loss
  // right after cannot leave the new name on an empty or partial file. Off by default, as cp,
  // VTK and most tools write: that costs 5-20 ms a file, often more than extracting it.
  explicit OutputFile(const std::string& path, bool sync = false);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  // Appends `size` bytes. Throws mvox::Error.
  void write(const void* data, std::size_t size) {
    if (const int error = writer_.write(data, size)) fail_write(error);
  }

  // Room for `size` bytes (at most BufferedWriter::kBufferBytes) to format into, then
  // commit(used) appends the `used` bytes written there. Throws mvox::Error.
  char* reserve(std::size_t size) {
    int error = 0;
    char* room = writer_.reserve(size, &error);
    if (room == nullptr) fail_write(error);
    return room;
  }
  void commit(std::size_t used) { writer_.commit(used); }

  // Appends the first `size` bytes of the file `fd` (a scratch file), copied by the kernel
  // where it can (BufferedWriter::append_file). Throws mvox::Error naming `what` when `fd` is
  // shorter, or naming the target when writing fails.
  void append_file(int fd, std::uint64_t size, const std::string& what);

  // Replaces bytes [offset, offset + size) already written, e.g. a header whose counts are
  // known only at the end. Requires can_overwrite() and offset + size <= bytes_written().
  void overwrite(std::uint64_t offset, const void* data, std::size_t size);

  // True when the bytes go to a temporary regular file, which can be overwritten and is renamed
  // by commit(); false for standard output, devices and pipes.
  bool can_overwrite() const { return !temp_path_.empty(); }

  // Flushes, syncs, closes and renames the temporary onto the target (for direct targets:
  // flushes and closes). Throws mvox::Error; on failure the target is untouched.
  void commit();

  // commit() in two steps, so that several files can appear together: seal() does all the I/O
  // that can still fail (flush, fsync, close); publish() (or publish_together) then only
  // renames. A sealed file that is never published is deleted like an uncommitted one.
  void seal();
  void publish();

  // Throws mvox::Error naming the target when publishing would fail for a reason that can be
  // seen beforehand: the target is immutable or append-only (chattr +i, +a), or it sits in a
  // sticky directory (like /tmp) and belongs to another user, or it has become a directory.
  // Direct targets always pass.
  void check_replaceable() const;

  std::uint64_t bytes_written() const { return writer_.bytes_written(); }

  // The temporary file the bytes go to until publishing; empty for direct targets. Other
  // processes may write into it too: the ranks of mvox-mpi write their parts of a mesh there.
  const std::string& temporary_path() const { return temp_path_; }

  // The target as given ("-" for standard output).
  const std::string& path() const { return path_; }
  // The name used in messages: the path, or "standard output".
  const std::string& subject() const { return subject_; }
  // Where companion temporary files belong: the target's directory when writing through a
  // temporary (same file system, so no surprise on a full disk), else the system's temporary
  // directory.
  std::string scratch_directory() const;

 private:
  friend void publish_together(const std::vector<OutputFile*>& files);
  [[noreturn]] void fail_write(int error);
  void close_fd();
  void open_descriptor(int fd);
  void open_direct(const std::string& path);
  void create_temporary();

  std::string path_;
  std::string subject_;
  std::string target_path_;  // path_ with symbolic links followed: what publish() replaces
  std::string temp_path_;    // empty for direct targets
  BufferedWriter writer_;
  int registration_ = 0;  // the record of this output in progress (termination.h)
  bool owns_fd_ = false;  // false for standard output and other descriptors named by path
  bool sync_ = false;     // fsync before the rename (the constructor's `sync`)
  bool failed_ = false;
  bool sealed_ = false;
  bool committed_ = false;
};

// Makes sealed `files` appear together. Every target is checked first (check_replaceable), so a
// refusal that can be seen beforehand changes nothing; then each temporary replaces its target.
// If a replacement still fails (the directory changed meanwhile), the ones already made are
// undone and the previous files come back, so the targets end all new or all as they were
// (except on file systems that cannot exchange two names, see termination.h). Interrupts wait
// meanwhile. Direct targets take part trivially. Throws mvox::Error naming the target at fault.
void publish_together(const std::vector<OutputFile*>& files);

}  // namespace mvox
