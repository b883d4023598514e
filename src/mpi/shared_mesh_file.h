#pragma once
// The one mesh file the ranks of mvox-mpi write together: rank 0's head, then each rank's part
// at offsets from an exclusive scan of the parts' sizes, with MPI-IO. PLY's parts have two
// sections, their vertex records and their face records, and every rank's vertices come before
// anyone's faces; STL's and OBJ's parts are one section each. Binary PLY and STL parts are
// written in place as they are extracted (placed_part_writer.h); the others wait in a part file
// each, copied in once every part's size is known.
#include <cstdint>
#include <string>
#include <vector>

#include "mpi/mpi_world.h"

namespace mvox {

// What each rank tells the others about its part.
struct PartShape {
  std::uint64_t vertex_bytes = 0;  // its bytes that go among the vertices (all, for OBJ and STL)
  std::uint64_t face_bytes = 0;    // those that go among the faces (PLY)
  std::uint64_t faces = 0;
};

struct PartOffsets {
  std::uint64_t vertex_at = 0;
  std::uint64_t face_at = 0;
};

// Where rank `rank`'s sections go, after a head of `head_bytes`.
PartOffsets part_offsets(const std::vector<PartShape>& shapes, int rank, std::uint64_t head_bytes);

// The file open on every rank, in agreed steps (MpiWorld::step): rank 0's temporary of the
// output, named `subject` in messages. After a failed step it is left open, deliberately: every
// rank then ends at once, and MPI_Finalize (~MpiWorld) closes it; a close in a destructor would
// be a collective call made while the ranks unwind.
class SharedMeshFile {
 public:
  // Collective: opens `path`. Throws as MpiWorld::step does.
  SharedMeshFile(MpiWorld& world, const std::string& path, const std::string& subject);
  SharedMeshFile(const SharedMeshFile&) = delete;
  SharedMeshFile& operator=(const SharedMeshFile&) = delete;

  MPI_File file() const { return file_; }
  const std::string& subject() const { return subject_; }

  // Collective: rank 0 writes `head` at the start; each rank with a part file (a non-empty
  // `part_path`) copies its vertex section, then its face section, as `shapes[rank]` says, to
  // its offsets (part_offsets). Throws as MpiWorld::step does.
  void write(const std::string& head, const std::vector<PartShape>& shapes,
             const std::string& part_path);
  // Collective: MPI_File_sync with `sync`, and close. Throws as MpiWorld::step does.
  void close(bool sync);

 private:
  MpiWorld& world_;
  std::string subject_;
  MPI_File file_ = MPI_FILE_NULL;
};

}  // namespace mvox
