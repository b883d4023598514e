#include "write/buffered_writer.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/vfs.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <utility>

namespace mvox {

// The writing thread: one buffer at a time, handed over under the mutex.
struct BufferedWriter::Background {
  std::mutex mutex;
  std::condition_variable changed;
  const char* data = nullptr;
  std::size_t size = 0;
  int fd = -1;
  bool busy = false;  // a buffer is handed over and not yet written
  bool stop = false;
  int error = 0;  // of the last write, until the owner takes it
  std::thread thread;

  void run() {
    std::unique_lock<std::mutex> lock(mutex);
    for (;;) {
      changed.wait(lock, [&] { return busy || stop; });
      if (!busy) return;
      lock.unlock();
      const int result = write_fully(fd, data, size);
      lock.lock();
      if (result != 0 && error == 0) error = result;
      busy = false;
      changed.notify_all();
    }
  }
};

namespace {
std::atomic<bool> background_writes{true};
}  // namespace

void BufferedWriter::allow_background_writes(bool allowed) {
  background_writes.store(allowed, std::memory_order_relaxed);
}

bool BufferedWriter::background_writes_allowed() {
  return background_writes.load(std::memory_order_relaxed);
}

BufferedWriter::BufferedWriter() : buffer_(new char[kBufferBytes]) {}

BufferedWriter::~BufferedWriter() {
  if (!background_) return;
  {
    std::unique_lock<std::mutex> lock(background_->mutex);
    background_->changed.wait(lock, [&] { return !background_->busy; });
    background_->stop = true;
    background_->changed.notify_all();
  }
  background_->thread.join();
}

void BufferedWriter::release() {
  if (background_) {
    {
      std::unique_lock<std::mutex> lock(background_->mutex);
      background_->changed.wait(lock, [&] { return !background_->busy; });
      background_->stop = true;
      background_->changed.notify_all();
    }
    background_->thread.join();
    background_.reset();
  }
  buffer_.reset();
  spare_.reset();
  used_ = 0;
}

namespace {

// tmpfs (/dev/shm, and /tmp on many systems) has no blocks to reserve: fallocate there takes
// and zero-fills memory pages ahead of the writes, which then fill them again. A 256x256x1024
// raw volume to PLY on tmpfs took 80.5 ms with it and 76.9 ms without (one thread, 15
// interleaved rounds).
bool allocating_ahead_pays(int fd) {
  struct statfs info {};
  if (::fstatfs(fd, &info) != 0) return false;
  constexpr decltype(info.f_type) kTmpfsMagic = 0x01021994;  // TMPFS_MAGIC, linux/magic.h
  return info.f_type != kTmpfsMagic;
}

}  // namespace

void BufferedWriter::set_fd(int fd, bool preallocate) {
  // A background write still uses the old descriptor: it must end before that is closed.
  if (background_) background_->error = wait_for_background();
  fd_ = fd;
  preallocate_ = preallocate && fd >= 0 && allocating_ahead_pays(fd);
  allocated_ = 0;
}

bool BufferedWriter::allocates_ahead() const { return preallocate_; }

void BufferedWriter::allocate_to(std::uint64_t end) {
  if (!preallocate_ || end <= allocated_) return;
  // At most 16 MiB past the bytes: near a full disk, room taken ahead could fail a write that
  // would have fitted.
  constexpr std::uint64_t kSmallestStep = std::uint64_t{1} << 20;
  constexpr std::uint64_t kLargestStep = std::uint64_t{16} << 20;
  const std::uint64_t step = std::min(std::max(allocated_, kSmallestStep), kLargestStep);
  const std::uint64_t target = std::max(end, allocated_ + step);
  if (::fallocate(fd_, FALLOC_FL_KEEP_SIZE, static_cast<off_t>(allocated_),
                  static_cast<off_t>(target - allocated_)) != 0) {
    preallocate_ = false;  // not supported here, or no room: the writes report a full disk
    return;
  }
  allocated_ = target;
}

int BufferedWriter::release_allocation() {
  // The file holds what was appended and is not in the buffer (all of it, after a flush).
  const std::uint64_t file_bytes = total_ - used_;
  if (allocated_ <= file_bytes || fd_ < 0) return 0;
  if (const int error = wait_for_background()) return error;
  allocated_ = 0;
  return ::ftruncate(fd_, static_cast<off_t>(file_bytes)) == 0 ? 0 : errno;
}

int BufferedWriter::wait_for_background() {
  if (!background_) return 0;
  std::unique_lock<std::mutex> lock(background_->mutex);
  background_->changed.wait(lock, [&] { return !background_->busy; });
  return std::exchange(background_->error, 0);
}

int BufferedWriter::hand_off() {
  if (used_ == 0) return wait_for_background();
  allocate_to(total_);
  if (!background_ && !background_writes.load(std::memory_order_relaxed)) {
    const int error = write_fully(fd_, buffer_.get(), used_);
    used_ = 0;
    return error;
  }
  if (!background_) {
    try {
      auto background = std::make_unique<Background>();
      spare_.reset(new char[kBufferBytes]);
      Background* started = background.get();
      background->thread = std::thread([started] { started->run(); });
      background_ = std::move(background);
    } catch (...) {
      // No thread or no memory for a second buffer: write as before, synchronously.
      spare_.reset();
      const int error = write_fully(fd_, buffer_.get(), used_);
      used_ = 0;
      return error;
    }
  }
  if (const int error = wait_for_background()) {
    used_ = 0;  // the file is dead: the owner reports the error and stops writing it
    return error;
  }
  std::swap(buffer_, spare_);
  {
    std::lock_guard<std::mutex> lock(background_->mutex);
    background_->data = spare_.get();
    background_->size = used_;
    background_->fd = fd_;
    background_->busy = true;
  }
  background_->changed.notify_all();
  used_ = 0;
  return 0;
}

int BufferedWriter::flush() {
  int error = wait_for_background();
  if (used_ > 0 && error == 0) {
    allocate_to(total_);
    error = write_fully(fd_, buffer_.get(), used_);
  }
  // Drop the bytes even after an error: the owner reports it and stops writing this file.
  used_ = 0;
  return error;
}

int BufferedWriter::write_slow(const void* data, std::size_t size) {
  if (size >= kBufferBytes) {
    // A block at least as large as the buffer gains nothing from a copy; written in order,
    // after everything before it.
    if (const int error = flush()) return error;
    allocate_to(total_ + size);
    if (const int error = write_fully(fd_, data, size)) return error;
    total_ += size;
    return 0;
  }
  if (const int error = hand_off()) return error;
  std::memcpy(buffer_.get(), data, size);
  used_ = size;
  total_ += size;
  return 0;
}

int BufferedWriter::append_by_splice(int from_fd, std::uint64_t* from, std::uint64_t* size,
                                     bool* short_source) {
  if (*size == 0) return 0;
  struct stat target {};
  if (::fstat(fd_, &target) != 0 || !S_ISREG(target.st_mode)) return -1;
  int ends[2];
  if (::pipe2(ends, O_CLOEXEC) != 0) return -1;
  struct Pipe {
    int* ends;
    ~Pipe() {
      ::close(ends[0]);
      ::close(ends[1]);
    }
  } pipe{ends};
  // A pipe of one buffer's size; a user's limit may refuse it, and the default 64 KiB pipe then
  // carries smaller chunks.
  const int pipe_bytes = ::fcntl(ends[1], F_SETPIPE_SZ, static_cast<int>(kBufferBytes));
  const std::size_t chunk = pipe_bytes > 0 ? static_cast<std::size_t>(pipe_bytes) : 65536;
  // The source is read at explicit offsets, so bytes in the pipe that the target refuses can be
  // read again another way: *from counts only bytes the target took.
  bool moved = false;
  while (*size > 0) {
    loff_t offset = static_cast<loff_t>(*from);
    const ssize_t got =
        ::splice(from_fd, &offset, ends[1], nullptr,
                 static_cast<std::size_t>(std::min<std::uint64_t>(*size, chunk)), SPLICE_F_MOVE);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) return !moved && (errno == EINVAL || errno == ENOSYS) ? -1 : errno;
    if (got == 0) {
      *short_source = true;
      return 0;
    }
    std::size_t in_pipe = static_cast<std::size_t>(got);
    while (in_pipe > 0) {
      const ssize_t put = ::splice(ends[0], nullptr, fd_, nullptr, in_pipe, SPLICE_F_MOVE);
      if (put < 0 && errno == EINTR) continue;
      if (put < 0) return !moved && errno == EINVAL ? -1 : errno;  // EINVAL: takes no splice
      if (put == 0) return ENOSPC;                                 // as write(2) returning 0
      in_pipe -= static_cast<std::size_t>(put);
      *from += static_cast<std::uint64_t>(put);
      *size -= static_cast<std::uint64_t>(put);
      total_ += static_cast<std::uint64_t>(put);
      moved = true;
    }
  }
  return 0;
}

int BufferedWriter::append_file(int from_fd, std::uint64_t size, bool* short_source) {
  *short_source = false;
  if (const int error = flush()) return error;
  allocate_to(total_ + size);  // for the whole copy at once
  std::uint64_t spliced_to = 0;
  if (const int result = append_by_splice(from_fd, &spliced_to, &size, short_source); result >= 0)
    return result;
  auto from = static_cast<loff_t>(spliced_to);
  bool kernel_copies = true;
  while (size > 0) {
    const std::size_t want =
        static_cast<std::size_t>(std::min<std::uint64_t>(size, std::uint64_t{1} << 30));
    ssize_t got = -1;
    if (kernel_copies) {
      got = ::copy_file_range(from_fd, &from, fd_, nullptr, want, 0);
      if (got < 0 && errno == EINTR) continue;
      // Another file system, a pipe or device as the target, an old kernel: copy it ourselves.
      if (got < 0 && (errno == EXDEV || errno == EINVAL || errno == ENOSYS || errno == EOPNOTSUPP ||
                      errno == EBADF)) {
        kernel_copies = false;
        continue;
      }
      if (got < 0) return errno;
    } else {
      const std::size_t chunk = std::min(want, kBufferBytes);
      got = ::pread(from_fd, buffer_.get(), chunk, from);
      if (got < 0 && errno == EINTR) continue;
      if (got < 0) return errno;
      if (got > 0) {
        if (const int error = write_fully(fd_, buffer_.get(), static_cast<std::size_t>(got)))
          return error;
        from += got;
      }
    }
    if (got == 0) {
      *short_source = true;
      return 0;
    }
    size -= static_cast<std::uint64_t>(got);
    total_ += static_cast<std::uint64_t>(got);
  }
  return 0;
}

int write_fully(int fd, const void* data, std::size_t size) {
  const char* bytes = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t written = ::write(fd, bytes, size);
    if (written < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    // write(2) returning 0 for a non-empty request means the device takes no more.
    if (written == 0) return ENOSPC;
    bytes += written;
    size -= static_cast<std::size_t>(written);
  }
  return 0;
}

}  // namespace mvox
