#include "modules/image_codecs.h"

#include <exception>
#include <new>

#include "error.h"
#include "modules/image_codecs/image_codecs_api.h"
#include "modules/module_loader.h"

namespace mvox {
namespace {

constexpr ModuleName kImageCodecs{
    "libmvox_image_codecs.so", "image codecs module (OpenCV)",
    "OpenCV's image codecs (apt-get install libopencv-imgcodecs-dev; scripts/install_deps.sh "
    "installs it)"};

struct Api {
  decltype(&mvox_image_codecs_initialize) initialize = nullptr;
  decltype(&mvox_image_decode) decode = nullptr;
  decltype(&mvox_image_can_write) can_write = nullptr;
  decltype(&mvox_image_encode) encode = nullptr;
};

// The module's functions, or mvox::Error(subject, why not). Slices are decoded on the reading
// thread while pictures are written on the main one, so the first use may come from either.
const Api& api(const std::string& subject) {
  return module_functions<Api>(
      kImageCodecs, "mvox_image_codecs_api_version", MVOX_IMAGE_CODECS_API_VERSION, subject,
      [&](void* handle, Api& functions) {
        auto resolve = [&](const char* symbol, auto** function) {
          resolve_function(handle, symbol, function, kImageCodecs, subject);
        };
        resolve("mvox_image_codecs_initialize", &functions.initialize);
        resolve("mvox_image_decode", &functions.decode);
        resolve("mvox_image_can_write", &functions.can_write);
        resolve("mvox_image_encode", &functions.encode);
      });
}

std::string depth_words(int depth) {
  switch (depth) {
    case MVOX_IMAGE_U8: return "8-bit unsigned";
    case MVOX_IMAGE_S8: return "8-bit signed";
    case MVOX_IMAGE_U16: return "16-bit unsigned";
    case MVOX_IMAGE_S16: return "16-bit signed";
    case MVOX_IMAGE_S32: return "32-bit integer";
    case MVOX_IMAGE_F32: return "32-bit float";
    case MVOX_IMAGE_F64: return "64-bit float";
    default: return "of an unknown sample type";
  }
}

// What crosses the module's C boundary for a destination: the caller's function, and what it
// threw, carried back to this side instead of unwinding through the module.
struct DestinationCall {
  const DecodedImageDestination* destination;
  std::exception_ptr thrown;
};

unsigned char* call_destination(void* context, const mvox_image_shape* shape) {
  auto* call = static_cast<DestinationCall*>(context);
  try {
    DecodedImageShape decoded;
    decoded.width = static_cast<std::uint32_t>(shape->width);
    decoded.height = static_cast<std::uint32_t>(shape->height);
    decoded.channels = shape->channels;
    decoded.depth_text = depth_words(shape->depth);
    decoded.readable = true;
    switch (shape->depth) {
      case MVOX_IMAGE_U8: decoded.type = SampleType::u8; break;
      case MVOX_IMAGE_U16: decoded.type = SampleType::u16; break;
      case MVOX_IMAGE_S16: decoded.type = SampleType::i16; break;
      default: decoded.readable = false;
    }
    return (*call->destination)(decoded);
  } catch (...) {
    call->thrown = std::current_exception();
    return nullptr;
  }
}

int append_bytes(void* context, const unsigned char* bytes, std::size_t size) {
  try {
    auto* out = static_cast<std::vector<unsigned char>*>(context);
    out->insert(out->end(), bytes, bytes + size);
    return 0;
  } catch (...) {
    return -1;
  }
}

}  // namespace

void load_image_codecs(const std::string& subject) { api(subject).initialize(); }

void decode_image_with_opencv(const std::string& path, const unsigned char* bytes, std::size_t size,
                              const DecodedImageDestination& destination) {
  const Api& functions = api(path);
  DestinationCall call{&destination, nullptr};
  char problem[1024] = "";
  const int status =
      functions.decode(bytes, size, &call_destination, &call, problem, sizeof problem);
  if (call.thrown) std::rethrow_exception(call.thrown);
  if (status != 0) throw Error(path, problem[0] != '\0' ? problem : "cannot decode image");
}

bool opencv_can_write(const std::string& path, const std::string& extension) {
  return api(path).can_write(extension.c_str()) == 1;
}

std::vector<unsigned char> encode_image_with_opencv(const std::string& path,
                                                    const std::string& extension,
                                                    const SliceView& slice) {
  const Api& functions = api(path);
  std::vector<unsigned char> encoded;
  const int bits = slice.type == SampleType::u8 ? 8 : 16;
  if (functions.encode(extension.c_str(), slice.samples, static_cast<int>(slice.width),
                       static_cast<int>(slice.height), slice.row_stride_bytes, bits, &append_bytes,
                       &encoded) != 0)
    throw Error(path, "cannot encode a " + std::string(sample_type_name(slice.type)) +
                          " image with extension '" + extension + "'");
  return encoded;
}

}  // namespace mvox
