#pragma once
// Between numpy and mvox: arrays handed to numpy without a copy, numpy dtypes as sample types
// and back, and the guard that keeps two Python threads out of one object.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "mvox/slice.h"
#include "write/mesh/mesh_arrays.h"

namespace mvox {
namespace py = pybind11;

// Numbers handed to numpy: the array owns them through a capsule, so nothing is copied.
template <class T>
py::array_t<T> to_numpy(ArrayOf<T>&& values, std::vector<py::ssize_t> shape) {
  auto* owned = new ArrayOf<T>(std::move(values));
  py::capsule owner(owned, [](void* p) { delete static_cast<ArrayOf<T>*>(p); });
  return py::array_t<T>(shape, owned->data(), owner);
}

// Marks an object in use for the length of a call that releases the GIL, so that a second
// Python thread calling it meanwhile gets a RuntimeError instead of racing on its buffers.
// Set and cleared while holding the GIL.
class InUse {
 public:
  InUse(bool& busy, const char* what) : busy_(busy) {
    if (busy_)
      throw std::runtime_error(std::string(what) +
                               " is in use by another thread; use one object per thread");
    busy_ = true;
  }
  ~InUse() { busy_ = false; }
  InUse(const InUse&) = delete;
  InUse& operator=(const InUse&) = delete;

 private:
  bool& busy_;
};

// The sample type of a numpy dtype mvox reads, or a TypeError naming what it got.
SampleType sample_type_of(const py::dtype& dtype, const char* what);

// The numpy dtype of a sample type.
py::dtype dtype_of(SampleType type);

}  // namespace mvox
