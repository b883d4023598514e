#include "write/output_file.h"

#include <fcntl.h>
#include <linux/fs.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <vector>

#include "error.h"
#include "mvox/assert.h"
#include "pipeline/termination.h"
#include "write/standard_descriptors.h"

namespace mvox {
namespace {

// The longest file name most file systems take (ext4, xfs, btrfs, tmpfs: 255 bytes).
constexpr std::size_t kMaxNameBytes = NAME_MAX;
constexpr int kMaxLinkHops = 40;  // as the kernel's own limit (ELOOP)

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

std::string name_part(const std::string& path) {
  const std::size_t slash = path.rfind('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

// The temporary's name for target file name `base`: ".BASE.XXXXXX", with BASE cut short (at a
// UTF-8 character boundary) when the whole would exceed kMaxNameBytes, so that any name the
// file system accepts as a target also gets a temporary.
std::string temporary_name_template(const std::string& base) {
  constexpr std::size_t kAddedBytes = 8;  // "." and ".XXXXXX"
  std::string kept = base;
  if (kept.size() + kAddedBytes > kMaxNameBytes) {
    std::size_t cut = kMaxNameBytes - kAddedBytes;
    while (cut > 0 && (static_cast<unsigned char>(kept[cut]) & 0xc0) == 0x80) --cut;
    kept.resize(cut);
  }
  return "." + kept + ".XXXXXX";
}

// True when `path` lies under /dev or /proc: device nodes and the kernel's files, which are
// written in place and never created or renamed over.
bool is_system_path(const std::string& path) {
  std::error_code error;
  std::filesystem::path absolute = std::filesystem::absolute(path, error);
  if (error) return false;
  // The directory with links followed (/dev/fd is a link into /proc), the name as it is.
  std::filesystem::path directory =
      std::filesystem::weakly_canonical(absolute.parent_path(), error);
  if (error) directory = absolute.parent_path().lexically_normal();
  const std::string text = directory.string();
  for (const char* root : {"/dev", "/proc"}) {
    const std::string prefix = root;
    if (text == prefix || text.compare(0, prefix.size() + 1, prefix + "/") == 0) return true;
  }
  return false;
}

// True when the process may replace other users' files in sticky directories (CAP_FOWNER),
// as root usually may; read from /proc, false where it cannot be read.
bool has_fowner_capability() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.compare(0, 7, "CapEff:") != 0) continue;
    const unsigned long long effective = std::strtoull(line.c_str() + 7, nullptr, 16);
    constexpr unsigned kCapFowner = 3;  // linux/capability.h
    return (effective >> kCapFowner) & 1u;
  }
  return false;
}

}  // namespace

OutputFile::OutputFile(const std::string& path, bool sync)
    : path_(path), subject_(path == "-" ? "standard output" : path), sync_(sync) {
  if (path_.empty()) throw Error("output file", "empty file name");
  if (path_ == "-") {
    open_descriptor(STDOUT_FILENO);
    return;
  }
  // Follow links one at a time: a link may lead to a descriptor (/dev/stdout is one), which is
  // written through, or to the file that is to be replaced while the link itself stays.
  std::string target = path_;
  for (int hop = 0;; ++hop) {
    if (const std::optional<int> fd = descriptor_named_by(target)) {
      open_descriptor(*fd);
      return;
    }
    struct stat link_status {};
    if (::lstat(target.c_str(), &link_status) != 0 || !S_ISLNK(link_status.st_mode)) break;
    if (hop == kMaxLinkHops) throw Error(subject_, "cannot create file: " + errno_text(ELOOP));
    std::vector<char> text(PATH_MAX + 1);
    const ssize_t length = ::readlink(target.c_str(), text.data(), text.size() - 1);
    if (length < 0) throw Error(subject_, "cannot follow the link: " + errno_text(errno));
    const std::string link(text.data(), static_cast<std::size_t>(length));
    target = link.front() == '/' ? link : directory_part(target) + link;
  }
  target_path_ = target;

  struct stat target_status {};
  const bool exists = ::stat(target_path_.c_str(), &target_status) == 0;
  if (exists && S_ISDIR(target_status.st_mode))
    throw Error(subject_, "cannot create file: Is a directory");
  // A device, pipe or socket, or anything under /dev and /proc: renaming onto it would replace
  // the node itself (as root, even /dev/null).
  if ((exists && !S_ISREG(target_status.st_mode)) || is_system_path(target_path_)) {
    open_direct(target_path_);
    return;
  }
  create_temporary();
}

void OutputFile::open_descriptor(int fd) {
  if (standard_descriptor_was_closed(fd))
    throw Error(subject_, (subject_ == descriptor_name(fd) ? "is" : descriptor_name(fd) + " is") +
                              std::string(" closed, so what mvox wrote there would be lost; give "
                                          "a file name or redirect it"));
  if (::fcntl(fd, F_GETFD) == -1)
    throw Error(subject_, descriptor_name(fd) + " is not open: " + errno_text(errno));
  writer_.set_fd(fd);
  registration_ = register_direct_output(subject_);
}

void OutputFile::open_direct(const std::string& path) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC | O_NOCTTY);
  if (fd < 0 && errno == ENOENT)
    throw Error(subject_, "cannot create file: " + errno_text(errno) +
                              " (mvox writes into existing files under /dev and /proc, never "
                              "creates any)");
  if (fd < 0) throw Error(subject_, "cannot open for writing: " + errno_text(errno));
  writer_.set_fd(fd);
  owns_fd_ = true;
  registration_ = register_direct_output(subject_);
}

void OutputFile::create_temporary() {
  const std::string base = name_part(target_path_);
  if (base.empty() || base == "." || base == "..")
    throw Error(subject_, "cannot create file: Is a directory");
  std::string temp = directory_part(target_path_) + temporary_name_template(base);
  std::vector<char> name(temp.begin(), temp.end());
  name.push_back('\0');
  // Registered as it is created, so that an interrupt deletes it (termination.h).
  const int fd = create_output_temporary(name.data(), subject_, &registration_);
  if (fd < 0) throw Error(subject_, "cannot create file: " + errno_text(errno));
  temp_path_ = name.data();
  writer_.set_fd(fd, true);  // a new regular file: its blocks are allocated ahead of the writes
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
  const int fd = writer_.fd();
  writer_.set_fd(-1);  // first: it waits for a background write to this descriptor
  if (owns_fd_ && fd >= 0) ::close(fd);
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
  // With `sync`, fsync before the rename: otherwise a power loss shortly after can leave the new
  // name on an empty file. Without it the rename is still atomic for every other process, and
  // a late error (NFS, quotas) is still caught by close() below.
  if (const int error = writer_.release_allocation()) fail_write(error);
  if (sync_ && ::fsync(writer_.fd()) != 0) fail_write(errno);
  const int fd = writer_.fd();
  writer_.set_fd(-1);
  if (::close(fd) != 0) fail_write(errno);
  sealed_ = true;
  writer_.release();  // a sealed file waiting to be published holds no buffers
}

void OutputFile::check_replaceable() const {
  if (temp_path_.empty()) return;
  struct stat target {};
  if (::lstat(target_path_.c_str(), &target) != 0) return;  // nothing to replace
  if (S_ISDIR(target.st_mode))
    throw Error(subject_, "cannot replace file: it has become a directory");
  // rename(2) over an immutable or append-only file fails with EPERM; say which.
  const int fd = ::open(target_path_.c_str(), O_RDONLY | O_NONBLOCK | O_NOFOLLOW | O_CLOEXEC);
  if (fd >= 0) {
    int flags = 0;
    const bool known = ::ioctl(fd, FS_IOC_GETFLAGS, &flags) == 0;
    ::close(fd);
    if (known && (flags & FS_IMMUTABLE_FL))
      throw Error(subject_, "cannot replace file: it is immutable (chattr +i)");
    if (known && (flags & FS_APPEND_FL))
      throw Error(subject_, "cannot replace file: it is append-only (chattr +a)");
  }
  // In a sticky directory (like /tmp) only the file's owner, the directory's owner or a process
  // with CAP_FOWNER may replace a file.
  std::string directory = directory_part(target_path_);
  if (directory.empty()) directory = ".";
  struct stat parent {};
  if (::stat(directory.c_str(), &parent) != 0 || !(parent.st_mode & S_ISVTX)) return;
  const uid_t me = ::geteuid();
  if (target.st_uid != me && parent.st_uid != me && !has_fowner_capability())
    throw Error(subject_, "cannot replace file: it belongs to another user (uid " +
                              std::to_string(target.st_uid) + ") in the sticky directory " +
                              directory);
}

void OutputFile::publish() { publish_together({this}); }

void OutputFile::commit() {
  seal();
  publish();
}

void OutputFile::append_file(int fd, std::uint64_t size, const std::string& what) {
  bool short_source = false;
  if (const int error = writer_.append_file(fd, size, &short_source)) fail_write(error);
  if (short_source) throw Error(what, "cannot read temporary file: it is shorter than written");
}

std::string OutputFile::scratch_directory() const {
  if (!temp_path_.empty()) {
    const std::string directory = directory_part(target_path_);
    return directory.empty() ? "." : directory;
  }
  std::error_code ignored;
  const std::filesystem::path temp = std::filesystem::temp_directory_path(ignored);
  return temp.empty() ? "/tmp" : temp.string();
}

void publish_together(const std::vector<OutputFile*>& files) {
  // An interrupt now waits for the renames, so that the outputs appear all or none.
  InterruptsDeferred publishing;
  for (const OutputFile* file : files) {
    MVOX_ASSERT(file->sealed_ && !file->committed_);
    file->check_replaceable();
  }
  std::vector<Publication> items;
  std::vector<OutputFile*> renamed;
  for (OutputFile* file : files) {
    if (file->temp_path_.empty()) continue;
    items.push_back({file->registration_, file->target_path_});
    renamed.push_back(file);
  }
  std::size_t failed = 0;
  if (const int error = publish_output_temporaries(items, &failed)) {
    renamed[failed]->failed_ = true;
    throw Error(renamed[failed]->subject_, "cannot replace file: " + errno_text(error));
  }
  for (OutputFile* file : files) {
    // A direct target only forgets its record; a renamed one was forgotten by the registry.
    if (file->temp_path_.empty()) discard_output(file->registration_);
    file->committed_ = true;
  }
}

}  // namespace mvox
