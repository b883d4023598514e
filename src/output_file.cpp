#include "output_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include "error.h"
#include "mvox/assert.h"
#include "termination.h"

namespace mvox {
namespace {

// mkstemp creates files with mode 0600; a finished output should get the usual 0666 & ~umask.
// umask() can only be read by setting it, so set it back at once (not thread-safe, but mvox
// creates its files from one thread).
mode_t default_file_mode() {
  const mode_t mask = ::umask(0);
  ::umask(mask);
  return static_cast<mode_t>(0666 & ~mask);
}

std::string directory_part(const std::string& path) {
  const std::size_t slash = path.rfind('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

}  // namespace

OutputFile::OutputFile(const std::string& path)
    : path_(path), subject_(path == "-" ? "standard output" : path) {
  if (path_.empty()) throw Error("output file", "empty file name");
  if (path_ == "-") {
    writer_.set_fd(STDOUT_FILENO);
    registration_ = register_direct_output(subject_);
    return;
  }

  struct stat target_status {};
  if (::stat(path_.c_str(), &target_status) == 0) {
    if (S_ISDIR(target_status.st_mode)) throw Error(subject_, "cannot create file: Is a directory");
    if (!S_ISREG(target_status.st_mode)) {
      // A device or pipe: renaming onto it would replace the node itself (as root, /dev/null).
      const int fd = ::open(path_.c_str(), O_WRONLY | O_CLOEXEC);
      if (fd < 0) throw Error(subject_, "cannot open for writing: " + errno_text(errno));
      writer_.set_fd(fd);
      owns_fd_ = true;
      registration_ = register_direct_output(subject_);
      return;
    }
  }

  const std::size_t slash = path_.rfind('/');
  const std::string base = slash == std::string::npos ? path_ : path_.substr(slash + 1);
  if (base.empty()) throw Error(subject_, "cannot create file: Is a directory");
  std::string temp = directory_part(path_) + "." + base + ".XXXXXX";
  std::vector<char> name(temp.begin(), temp.end());
  name.push_back('\0');
  // Registered as it is created, so that an interrupt deletes it (termination.h).
  const int fd = create_output_temporary(name.data(), subject_, &registration_);
  if (fd < 0) throw Error(subject_, "cannot create file: " + errno_text(errno));
  temp_path_ = name.data();
  writer_.set_fd(fd);
  owns_fd_ = true;
  if (::fchmod(fd, default_file_mode()) != 0) {
    const int error = errno;
    close_fd();
    discard_output(registration_);
    throw Error(subject_, "cannot create file: " + errno_text(error));
  }
}

OutputFile::~OutputFile() {
  // Unflushed bytes are dropped on purpose: a direct target (standard output) gets no more of
  // an output that failed.
  close_fd();
  // Deletes the temporary unless it was published.
  if (!committed_) discard_output(registration_);
}

void OutputFile::close_fd() {
  if (owns_fd_ && writer_.fd() >= 0) ::close(writer_.fd());
  writer_.set_fd(-1);
}

void OutputFile::fail_write(int error) {
  failed_ = true;
  // The reader of a pipe has gone: main ends quietly rather than report it (termination.h).
  if (error == EPIPE) note_broken_pipe();
  throw Error(subject_, "write failed: " + errno_text(error));
}

void OutputFile::overwrite(std::uint64_t offset, const void* data, std::size_t size) {
  MVOX_ASSERT(can_overwrite());
  MVOX_ASSERT(offset <= bytes_written() && size <= bytes_written() - offset);
  if (failed_) throw Error(subject_, "write failed earlier");
  if (const int error = writer_.flush()) fail_write(error);
  const char* bytes = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t written = ::pwrite(writer_.fd(), bytes, size, static_cast<off_t>(offset));
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) fail_write(written < 0 ? errno : ENOSPC);
    bytes += written;
    size -= static_cast<std::size_t>(written);
    offset += static_cast<std::uint64_t>(written);
  }
}

void OutputFile::seal() {
  MVOX_ASSERT(!sealed_);
  if (failed_) throw Error(subject_, "write failed earlier");
  if (const int error = writer_.flush()) fail_write(error);
  if (temp_path_.empty()) {
    // Standard output stays open for whoever writes next; a device or pipe is closed here so
    // that its close error (rare, but possible) is reported.
    if (owns_fd_) {
      const int fd = writer_.fd();
      writer_.set_fd(-1);
      if (::close(fd) != 0) fail_write(errno);
    }
    sealed_ = true;
    return;
  }
  // fsync before rename: otherwise a crash shortly after can leave the new name on an empty
  // file, and some file systems (NFS, quotas) report ENOSPC only here or at close.
  if (::fsync(writer_.fd()) != 0) fail_write(errno);
  const int fd = writer_.fd();
  writer_.set_fd(-1);
  if (::close(fd) != 0) fail_write(errno);
  sealed_ = true;
}

void OutputFile::publish() {
  MVOX_ASSERT(sealed_ && !committed_);
  if (!temp_path_.empty()) {
    if (const int error = publish_output_temporary(registration_, path_)) {
      failed_ = true;
      throw Error(subject_, "cannot replace file: " + errno_text(error));
    }
  } else {
    discard_output(registration_);  // a direct target: only forgets the record
  }
  committed_ = true;
}

void OutputFile::commit() {
  seal();
  publish();
}

std::string OutputFile::scratch_directory() const {
  if (!temp_path_.empty()) {
    const std::string directory = directory_part(path_);
    return directory.empty() ? "." : directory;
  }
  std::error_code ignored;
  const std::filesystem::path temp = std::filesystem::temp_directory_path(ignored);
  return temp.empty() ? "/tmp" : temp.string();
}

}  // namespace mvox
