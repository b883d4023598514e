#include "volume_files.h"

#include <fstream>

namespace mvox::test::volume_files {

void write_file(const std::string& path, const std::string& text,
                const std::vector<unsigned char>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  ASSERT_TRUE(out.good()) << path;
}

const char* order_name(ByteOrder order) { return order == ByteOrder::big ? "big" : "little"; }

std::string metaimage_fields(const std::string& element_type, const std::string& extra) {
  return std::string("ObjectType = Image\nNDims = 3\nDimSize = ") + kSizes +
         "\nElementType = " + element_type + "\n" + extra;
}

void expect_axes(const VolumeInfo& info, const double (&axes)[3][3], const double (&spacing)[3]) {
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(info.spacing[a], spacing[a], 1e-12) << "axis " << a;
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(info.axes[a][i], axes[a][i], 1e-12) << a << "," << i;
  }
}

}  // namespace mvox::test::volume_files
