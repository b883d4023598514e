#include "numpy_interop.h"

#include <cstdint>

namespace mvox {

SampleType sample_type_of(const py::dtype& dtype, const char* what) {
  // By kind, size and byte order, not by identity: a dtype that came through pickle (say, from
  // multiprocessing) is an equal but distinct object.
  const char kind = dtype.kind();
  const py::ssize_t size = dtype.itemsize();
  const char order = py::str(dtype.attr("byteorder")).cast<std::string>()[0];
  const std::uint16_t one = 1;
  const bool little_host = *reinterpret_cast<const unsigned char*>(&one) == 1;
  const bool native = order == '=' || order == '|' || order == (little_host ? '<' : '>');
  if (native && kind == 'u' && size == 1) return SampleType::u8;
  if (native && kind == 'u' && size == 2) return SampleType::u16;
  if (native && kind == 'i' && size == 2) return SampleType::i16;
  if (native && kind == 'f' && size == 4) return SampleType::f32;
  const std::string name = py::str(py::handle(dtype)).cast<std::string>();
  throw py::type_error(std::string(what) + " has dtype " + name +
                       "; mvox reads uint8, uint16, int16 and float32 (native byte order): "
                       "convert it first, e.g. volume.astype(numpy.float32)");
}

py::dtype dtype_of(SampleType type) {
  switch (type) {
    case SampleType::u8: return py::dtype::of<std::uint8_t>();
    case SampleType::u16: return py::dtype::of<std::uint16_t>();
    case SampleType::i16: return py::dtype::of<std::int16_t>();
    case SampleType::f32: return py::dtype::of<float>();
  }
  return py::dtype::of<float>();
}

}  // namespace mvox
