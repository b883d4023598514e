#pragma once
// What a reader can tell of the cost of its slices: whether each is only bytes copied from a
// regular file or from memory (raw samples, at most byte-swapped, widened or scaled sample by
// sample), with nothing to decode and no pipe to wait on. A reading thread beside one engine
// then has nothing to overlap, and handing it the slices costs more than it saves
// (one_engine_helpers, pipeline/mesh_job.h). Readers that decode (PNG, JPEG, compressed TIFF,
// gzip NRRD, zlib MetaImage, DICOM) or may read a pipe either do not implement this or answer
// false.
namespace mvox {

class CopiedSlices {
 public:
  virtual bool slices_are_copied() const = 0;

 protected:
  ~CopiedSlices() = default;
};

}  // namespace mvox
