#pragma once
#include <cstddef>

#include "write/mesh/uninitialized_array.h"

namespace mvox {

// Formatted records, appended: a slab worker's faces (face_formatter.h) or vertex lines
// (vertex_text_formatter.h), made ahead of the file. A Sink for binary_records.h. Its storage
// only grows, keeps its size when emptied, and leaves the room it grows by unwritten
// (uninitialized_array.h): every byte appended is written by the formatter first.
class FormattedRecords {
 public:
  void* reserve(std::size_t bytes) {
    if (storage_.size() < used_ + bytes) storage_.resize(used_ + bytes);
    return storage_.data() + used_;
  }
  void commit(std::size_t bytes) { used_ += bytes; }
  // Forgets everything from byte `size` on.
  void truncate(std::size_t size) { used_ = size < used_ ? size : used_; }
  void clear() { used_ = 0; }
  void reserve_capacity(std::size_t bytes) { storage_.reserve(bytes); }

  const unsigned char* data() const { return storage_.data(); }
  std::size_t size() const { return used_; }

 private:
  UninitializedArray<unsigned char> storage_;
  std::size_t used_ = 0;
};

}  // namespace mvox
