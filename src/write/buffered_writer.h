#pragma once
// Buffered appends to a POSIX file descriptor, shared by OutputFile and ScratchFile.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>

namespace mvox {

// Collects small writes in one large buffer and hands them to write(2) in big blocks.
// Reports failures as errno values instead of throwing, so that each owner can name its own
// file in the Error it throws. Does not own the descriptor.
//
// From the second full buffer on, full buffers are written by a thread of its own while the
// caller fills the other buffer: the kernel's copy of the bytes into the page cache, as long as
// formatting them, then overlaps the caller's work (the engine's extraction) instead of adding
// to it. An output under one buffer never starts the thread. An error of a background write is
// returned by the next call that writes or flushes. Memory: two buffers once the thread runs.
class BufferedWriter {
 public:
  // Large enough that write(2) calls cost nothing next to formatting; allocated once.
  static constexpr std::size_t kBufferBytes = std::size_t{1} << 20;

  // Process-wide: whether full buffers may be written by a thread of their own (the default).
  // Off, every writer writes on its caller's thread: `mvox extract --threads 1`, so that a run
  // on a single-core device takes one thread.
  static void allow_background_writes(bool allowed);
  static bool background_writes_allowed();

  BufferedWriter();
  ~BufferedWriter();  // waits for a background write in progress; buffered bytes are dropped
  BufferedWriter(const BufferedWriter&) = delete;
  BufferedWriter& operator=(const BufferedWriter&) = delete;

  // Waits for a background write in progress first: the descriptor may then be closed.
  // `preallocate`: the descriptor is a new regular file, written from its start, whose blocks
  // are then allocated ahead of the writes (fallocate, keeping the size), 1 MiB, then as much
  // again as the file holds, up to 16 MiB at a time. On ext4 a write into blocks not yet
  // allocated reserves them page by page, which cost writing 250 MB three times what writing
  // into allocated blocks did (0.3 against 0.1 s). Where fallocate fails (another file system,
  // a full disk) the writes go on without it. release_allocation() frees what is left past the
  // end.
  // Not on tmpfs, where there are no blocks and fallocate would zero-fill memory pages the writes
  // then fill again.
  void set_fd(int fd, bool preallocate = false);
  // Whether the writes go into blocks allocated ahead (set_fd's `preallocate`, where it pays).
  bool allocates_ahead() const;
  int fd() const { return fd_; }

  // After the last flush: frees the blocks allocated ahead past the end of the file (ftruncate
  // to its own size). Returns 0 or an errno value.
  int release_allocation();

  // Appends `size` bytes. Returns 0, or the errno of a failed write(2).
  int write(const void* data, std::size_t size) {
    // Inline fast path: the hot loops of the mesh writers append a few bytes at a time.
    if (size <= kBufferBytes - used_) {
      std::memcpy(buffer_.get() + used_, data, size);
      used_ += size;
      total_ += size;
      return 0;
    }
    return write_slow(data, size);
  }

  // Room for up to `size` bytes (at most kBufferBytes) in the buffer, flushing it first when it
  // has less: the caller formats records there directly, then commits what it used. Returns
  // nullptr with *error set when the flush fails.
  char* reserve(std::size_t size, int* error) {
    if (size > kBufferBytes - used_) {
      *error = hand_off();
      if (*error != 0) return nullptr;
    }
    return buffer_.get() + used_;
  }
  // Counts `size` bytes written at reserve()'s address as appended.
  void commit(std::size_t size) {
    used_ += size;
    total_ += size;
  }

  // Hands the buffered bytes to the descriptor, and waits for a background write: every byte
  // appended is in the descriptor when it returns 0. Returns 0 or an errno value.
  int flush();

  // Appends `size` bytes of the file `from_fd` from offset 0, copied by the kernel: through a
  // pipe with splice(2) into a regular file (the source's pages go into the pipe by reference,
  // so the bytes are copied once; copy_file_range, the next choice, copies them twice on ext4,
  // into pipe pages of its own and then into the target's: 20 against 15 ms for the 30 MB of a
  // PLY's faces here), else copy_file_range, else through the buffer where the kernel cannot.
  // Flushes first. Returns 0 or an errno value; *short_source is set when `from_fd` holds fewer
  // bytes.
  int append_file(int from_fd, std::uint64_t size, bool* short_source);

  // Bytes appended so far, buffered or not.
  std::uint64_t bytes_written() const { return total_; }

  // After the last flush: ends the writing thread and frees both buffers, so that a file kept
  // only to be published later (one per label, mvox extract --labels) holds no memory. Nothing
  // may be written after it.
  void release();

 private:
  struct Background;

  // append_file's first way: moves bytes of `from_fd` from offset *from into the file until
  // *size is 0 or the source ends (*short_source), advancing both by what the file took.
  // Returns 0, an errno value, or -1 when splice cannot be used here before any byte moved (the
  // caller goes on another way from *from).
  int append_by_splice(int from_fd, std::uint64_t* from, std::uint64_t* size, bool* short_source);

  int write_slow(const void* data, std::size_t size);
  // Gives the full buffer to the writing thread (started at the first call) and takes the
  // other one; writes synchronously when no thread can be had. Returns 0 or an errno value.
  int hand_off();
  // Waits until the writing thread is idle; returns the errno of its last write, or 0.
  int wait_for_background();
  // When preallocating: allocates the file's first `end` bytes, and a step beyond, if they are
  // not yet. Called before bytes go to the descriptor, with where they will end.
  void allocate_to(std::uint64_t end);

  std::unique_ptr<char[]> buffer_;
  std::unique_ptr<char[]> spare_;           // the other buffer, once the thread runs
  std::unique_ptr<Background> background_;  // the writing thread, once started
  std::size_t used_ = 0;
  std::uint64_t total_ = 0;
  int fd_ = -1;
  bool preallocate_ = false;
  std::uint64_t allocated_ = 0;  // bytes of the file allocated ahead, from its start
};

// write(2) until every byte is out, retrying after signals and partial writes.
// Returns 0 or an errno value.
int write_fully(int fd, const void* data, std::size_t size);

}  // namespace mvox
