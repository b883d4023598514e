#include "write/scratch_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <vector>

#include "error.h"
#include "pipeline/termination.h"
#include "write/deferred_close.h"
#include "write/output_file.h"

namespace mvox {

ScratchFile::ScratchFile(const std::string& directory, const std::string& subject)
    : subject_(subject) {
  std::string temp = directory;
  if (temp.empty()) temp = ".";
  if (temp.back() != '/') temp += '/';
  temp += ".mvox-scratch.XXXXXX";
  std::vector<char> name(temp.begin(), temp.end());
  name.push_back('\0');
  // The open descriptor keeps the data; the name is not needed, and without it nothing is left
  // behind. Created and unlinked in one step that an interrupt cannot split (termination.h).
  const int fd = create_nameless_temporary(name.data());
  if (fd < 0) {
    throw Error(subject_,
                "cannot create temporary file in " + directory + ": " + errno_text(errno));
  }
  writer_.set_fd(fd, true);  // blocks allocated ahead; freed with the file when it is closed
}

ScratchFile::~ScratchFile() {
  const int fd = writer_.fd();
  writer_.set_fd(-1);  // first: it waits for a background write to this descriptor
  if (fd >= 0) ::close(fd);
}

void ScratchFile::fail_write(int error) {
  throw Error(subject_, "write failed on temporary file: " + errno_text(error));
}

void ScratchFile::read_at(std::uint64_t offset, void* data, std::size_t size) {
  if (const int error = writer_.flush()) fail_write(error);
  auto* bytes = static_cast<char*>(data);
  while (size > 0) {
    const ssize_t got = ::pread(writer_.fd(), bytes, size, static_cast<off_t>(offset));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0)
      throw Error(subject_, "read failed on temporary file: " +
                                (got < 0 ? errno_text(errno) : std::string("it ended early")));
    bytes += got;
    size -= static_cast<std::size_t>(got);
    offset += static_cast<std::uint64_t>(got);
  }
}

void ScratchFile::copy_to(OutputFile& out) {
  if (const int error = writer_.flush()) fail_write(error);
  out.append_file(writer_.fd(), writer_.bytes_written(), subject_);
  // The last use: the descriptor and the buffers go now, not when the owner does; the pages go
  // on another thread while the run publishes (deferred_close.h).
  const int fd = writer_.fd();
  const std::uint64_t bytes = writer_.bytes_written();
  writer_.set_fd(-1);
  close_when_unneeded(fd, bytes);
  writer_.release();
}

}  // namespace mvox
