#include "mpi/shared_mesh_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

#include "error.h"
#include "mpi/mpi_file_stream.h"

namespace mvox {
namespace {

// Writes `size` bytes of the file `fd` from `from` into `file` at `at`, a MiB at a time.
void copy_into(MPI_File file, int fd, std::uint64_t from, std::uint64_t size, std::uint64_t at,
               const std::string& subject) {
  std::vector<char> buffer(std::size_t{1} << 20);
  while (size > 0) {
    const std::size_t want = static_cast<std::size_t>(std::min<std::uint64_t>(size, buffer.size()));
    const ssize_t got = ::pread(fd, buffer.data(), want, static_cast<off_t>(from));
    if (got <= 0)
      throw Error(subject, "cannot read back this rank's part: " +
                               (got < 0 ? errno_text(errno) : std::string("file too short")));
    write_fully_at(file, at, buffer.data(), static_cast<std::size_t>(got), subject);
    from += static_cast<std::uint64_t>(got);
    at += static_cast<std::uint64_t>(got);
    size -= static_cast<std::uint64_t>(got);
  }
}

}  // namespace

PartOffsets part_offsets(const std::vector<PartShape>& shapes, int rank, std::uint64_t head_bytes) {
  PartOffsets at;
  at.vertex_at = head_bytes;
  std::uint64_t all_vertex_bytes = 0, faces_before = 0;
  for (std::size_t r = 0; r < shapes.size(); ++r) {
    if (static_cast<int>(r) < rank) {
      at.vertex_at += shapes[r].vertex_bytes;
      faces_before += shapes[r].face_bytes;
    }
    all_vertex_bytes += shapes[r].vertex_bytes;
  }
  at.face_at = head_bytes + all_vertex_bytes + faces_before;
  return at;
}

SharedMeshFile::SharedMeshFile(MpiWorld& world, const std::string& path, const std::string& subject)
    : world_(world), subject_(subject) {
  const int opened =
      MPI_File_open(world.comm(), path.c_str(), MPI_MODE_WRONLY, MPI_INFO_NULL, &file_);
  world.step([&] {
    if (opened != MPI_SUCCESS)
      throw Error(subject_, "cannot open for the ranks to write: " + mpi_error_text(opened));
  });
}

void SharedMeshFile::write(const std::string& head, const std::vector<PartShape>& shapes,
                           const std::string& part_path) {
  world_.step([&] {
    if (world_.rank() == 0) write_fully_at(file_, 0, head.data(), head.size(), subject_);
    if (part_path.empty()) return;
    const PartShape& shape = shapes[static_cast<std::size_t>(world_.rank())];
    const PartOffsets at = part_offsets(shapes, world_.rank(), head.size());
    const int fd = ::open(part_path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw Error(subject_, "cannot read back this rank's part: " + errno_text(errno));
    try {
      copy_into(file_, fd, 0, shape.vertex_bytes, at.vertex_at, subject_);
      copy_into(file_, fd, shape.vertex_bytes, shape.face_bytes, at.face_at, subject_);
    } catch (...) {
      ::close(fd);
      throw;
    }
    ::close(fd);
  });
}

void SharedMeshFile::close(bool sync) {
  // Collective calls, made by every rank whatever the step found.
  const int synced = sync ? MPI_File_sync(file_) : MPI_SUCCESS;
  const int closed = MPI_File_close(&file_);
  world_.step([&] {
    if (synced != MPI_SUCCESS) throw Error(subject_, "sync failed: " + mpi_error_text(synced));
    if (closed != MPI_SUCCESS) throw Error(subject_, "close failed: " + mpi_error_text(closed));
  });
}

}  // namespace mvox
