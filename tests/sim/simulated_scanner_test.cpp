// The simulated scanner (sim/simulated_scanner.h) against the sample mapping it promises: slices
// in order through one reused buffer, rewind, spacing and origin, rounding and clamping for
// every sample type, thresholds exact for binary phantoms, and axes kept straight.
#include "simulated_scanner.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include "phantom_factory.h"
#include "phantom_measures.h"
#include "shapes.h"

namespace mvox::sim {
namespace {

using test::AxisPhantom;

// One row of given densities (width = values.size(), height = depth = 1).
class RowPhantom final : public Phantom {
 public:
  explicit RowPhantom(std::vector<float> values) : values_(std::move(values)) {}
  Grid grid() const override { return {static_cast<std::uint32_t>(values_.size()), 1, 1}; }
  float density(std::uint32_t x, std::uint32_t, std::uint32_t) const override { return values_[x]; }
  const char* name() const override { return "row"; }

 private:
  std::vector<float> values_;
};

// Reads sample (x, y) of a slice view as a double, whatever its type.
double sample_at(const SliceView& view, std::uint32_t x, std::uint32_t y) {
  const char* p = static_cast<const char*>(view.samples) + y * view.row_stride_bytes +
                  x * sample_bytes(view.type);
  switch (view.type) {
    case SampleType::u8: {
      std::uint8_t v;
      std::memcpy(&v, p, sizeof v);
      return v;
    }
    case SampleType::u16: {
      std::uint16_t v;
      std::memcpy(&v, p, sizeof v);
      return v;
    }
    case SampleType::i16: {
      std::int16_t v;
      std::memcpy(&v, p, sizeof v);
      return v;
    }
    case SampleType::f32: {
      float v;
      std::memcpy(&v, p, sizeof v);
      return v;
    }
  }
  return 0;
}

// Every sample of a scan, x fastest, through the scanner's own views (stride included).
std::vector<double> scan_all(SimulatedScanner& scanner) {
  std::vector<double> samples;
  SliceView view;
  while (scanner.next_slice(&view)) {
    for (std::uint32_t y = 0; y < view.height; ++y) {
      for (std::uint32_t x = 0; x < view.width; ++x) samples.push_back(sample_at(view, x, y));
    }
  }
  return samples;
}

const SampleType kAllTypes[] = {SampleType::u8, SampleType::u16, SampleType::i16, SampleType::f32};

TEST(ScannerTest, YieldsDepthSlicesThenFalse) {
  const auto sphere = make_phantom("sphere", {7, 5, 6}, 0);
  for (SampleType type : kAllTypes) {
    SimulatedScanner scanner(*sphere, default_scan_options(type));
    const VolumeInfo& info = scanner.info();
    EXPECT_EQ(info.width, 7u);
    EXPECT_EQ(info.height, 5u);
    EXPECT_EQ(info.depth, 6u);
    EXPECT_EQ(info.type, type);
    SliceView view;
    std::set<const void*> buffers;
    std::uint32_t slices = 0;
    while (scanner.next_slice(&view)) {
      ++slices;
      EXPECT_EQ(view.width, 7u);
      EXPECT_EQ(view.height, 5u);
      EXPECT_EQ(view.type, type);
      EXPECT_EQ(view.row_stride_bytes, 7 * sample_bytes(type));
      buffers.insert(view.samples);
      ASSERT_LE(slices, 6u);
    }
    EXPECT_EQ(slices, 6u) << sample_type_name(type);
    EXPECT_EQ(buffers.size(), 1u) << "one slice buffer, reused";
    EXPECT_FALSE(scanner.next_slice(&view));
  }
}

TEST(ScannerTest, RewindStreamsTheSameSlicesAgain) {
  const auto blobs = make_phantom("blobs", {12, 10, 9}, 4);
  SimulatedScanner scanner(*blobs, default_scan_options(SampleType::u16));
  const std::vector<double> first = scan_all(scanner);
  EXPECT_EQ(first.size(), 12u * 10 * 9);
  scanner.rewind();
  EXPECT_EQ(scan_all(scanner), first);
  // Rewinding half-way restarts at slice 0 too.
  scanner.rewind();
  SliceView view;
  ASSERT_TRUE(scanner.next_slice(&view));
  ASSERT_TRUE(scanner.next_slice(&view));
  scanner.rewind();
  EXPECT_EQ(scan_all(scanner), first);
}

TEST(ScannerTest, InfoCarriesSpacingAndOrigin) {
  const auto sphere = make_phantom("sphere", {8, 8, 8}, 0);
  ScanOptions options;
  options.spacing[0] = 0.5;
  options.spacing[1] = 0.75;
  options.spacing[2] = 2.0;
  options.origin[2] = -10;
  SimulatedScanner scanner(*sphere, options);
  EXPECT_EQ(scanner.info().spacing[0], 0.5);
  EXPECT_EQ(scanner.info().spacing[1], 0.75);
  EXPECT_EQ(scanner.info().spacing[2], 2.0);
  EXPECT_EQ(scanner.info().origin[0], 0.0);
  EXPECT_EQ(scanner.info().origin[2], -10.0);
}

TEST(ScannerTest, RoundsAndClampsForEachType) {
  const RowPhantom row({-1e4f, -1, -0.25f, 0, 0.04f, 0.06f, 0.25f, 1, 1e4f});
  struct Case {
    SampleType type;
    double offset;
    std::vector<double> expected;
  };
  const Case cases[] = {
      {SampleType::u8, 0, {0, 0, 0, 0, 0, 1, 3, 10, 255}},
      {SampleType::u16, 0, {0, 0, 0, 0, 0, 1, 3, 10, 65535}},
      {SampleType::i16, 0, {-32768, -10, -3, 0, 0, 1, 3, 10, 32767}},  // halves away from 0
      {SampleType::f32, 0.5, {-99999.5, -9.5, -2, 0.5, 0.9, 1.1, 3, 10.5, 100000.5}},
  };
  for (const Case& c : cases) {
    ScanOptions options;
    options.type = c.type;
    options.scale = 10;
    options.offset = c.offset;
    SimulatedScanner scanner(row, options);
    const std::vector<double> samples = scan_all(scanner);
    ASSERT_EQ(samples.size(), c.expected.size());
    for (std::size_t i = 0; i < samples.size(); ++i) {
      EXPECT_FLOAT_EQ(samples[i], c.expected[i]) << sample_type_name(c.type) << " sample " << i;
    }
  }
}

TEST(ScannerTest, DefaultOptionsMapZeroAndOne) {
  const RowPhantom row({0, 1});
  const double expected[][2] = {{0, 255}, {0, 4095}, {-1024, 2047}, {0, 1}};
  int i = 0;
  for (SampleType type : kAllTypes) {
    SimulatedScanner scanner(row, default_scan_options(type));
    const std::vector<double> samples = scan_all(scanner);
    EXPECT_EQ(samples[0], expected[i][0]) << sample_type_name(type);
    EXPECT_EQ(samples[1], expected[i][1]) << sample_type_name(type);
    ++i;
  }
}

TEST(ScannerTest, SampleThresholdIsExactForBinaryPhantoms) {
  const Grid g{16, 13, 11};
  const Sphere sphere(g, {9, 6, 5}, 4.5);
  const std::vector<float> densities = sample_volume(sphere);
  for (SampleType type : kAllTypes) {
    const ScanOptions options = default_scan_options(type);
    SimulatedScanner scanner(sphere, options);
    const std::vector<double> samples = scan_all(scanner);
    ASSERT_EQ(samples.size(), densities.size());
    for (double t : {0.0001, 0.001, 0.25, 0.5, 0.999, 1.0}) {
      const double s = sample_threshold(t, options);
      for (std::size_t i = 0; i < samples.size(); ++i) {
        ASSERT_EQ(densities[i] >= t, samples[i] >= s)
            << sample_type_name(type) << " t = " << t << " voxel " << i;
      }
    }
  }
  EXPECT_EQ(sample_threshold(0.5, default_scan_options(SampleType::u8)), 128);
  EXPECT_EQ(sample_threshold(0.5, default_scan_options(SampleType::u16)), 2048);
  EXPECT_EQ(sample_threshold(0.5, default_scan_options(SampleType::i16)), 512);
  EXPECT_EQ(sample_threshold(0.5, default_scan_options(SampleType::f32)), 0.5);
  // Out of range thresholds clamp to the type.
  EXPECT_EQ(sample_threshold(2.0, default_scan_options(SampleType::u8)), 255);
  EXPECT_EQ(sample_threshold(-1.0, default_scan_options(SampleType::u8)), 0);
}

TEST(ScannerTest, SampleThresholdSeparatesSheppLoganLevels) {
  // The default Shepp-Logan threshold must keep brain (0.2) and bright features (0.3) apart
  // after quantisation to every sample type.
  const double t = default_density_threshold("shepp-logan");
  for (SampleType type : kAllTypes) {
    const ScanOptions options = default_scan_options(type);
    const double s = sample_threshold(t, options);
    EXPECT_LT(sample_value(0.2f, options), s) << sample_type_name(type);
    EXPECT_GE(sample_value(0.3f, options), s) << sample_type_name(type);
  }
}

TEST(ScannerTest, AsymmetricGridKeepsAxesStraight) {
  const Grid g{7, 5, 6};
  // A sphere off the grid centre (3, 2, 2.5) on x only.
  const Sphere sphere(g, {4, 2, 2.5}, 1.6);
  SimulatedScanner scanner(sphere, default_scan_options(SampleType::u8));
  SliceView view;
  double sum[3] = {0, 0, 0};
  int inner = 0;
  for (std::uint32_t z = 0; scanner.next_slice(&view); ++z) {
    for (std::uint32_t y = 0; y < view.height; ++y)
      for (std::uint32_t x = 0; x < view.width; ++x) {
        const bool expected =
            std::pow(x - 4.0, 2) + std::pow(y - 2.0, 2) + std::pow(z - 2.5, 2) <= 1.6 * 1.6;
        const bool is_inner = sample_at(view, x, y) >= 128;
        ASSERT_EQ(is_inner, expected) << x << "," << y << "," << z;
        if (is_inner) {
          sum[0] += x;
          sum[1] += y;
          sum[2] += z;
          ++inner;
        }
      }
  }
  ASSERT_GT(inner, 0);
  EXPECT_DOUBLE_EQ(sum[0] / inner, 4.0);  // shifted by +1 from the grid centre in x
  EXPECT_DOUBLE_EQ(sum[1] / inner, 2.0);
  EXPECT_DOUBLE_EQ(sum[2] / inner, 2.5);

  // Every voxel distinct: the f32 sample at (column x, row y, slice z) is x + 10 y + 100 z.
  const AxisPhantom axis(g);
  SimulatedScanner axis_scanner(axis, default_scan_options(SampleType::f32));
  for (std::uint32_t z = 0; axis_scanner.next_slice(&view); ++z) {
    ASSERT_LT(z, 6u);
    for (std::uint32_t y = 0; y < 5; ++y)
      for (std::uint32_t x = 0; x < 7; ++x)
        ASSERT_EQ(sample_at(view, x, y), x + 10.0 * y + 100.0 * z);
  }
}

TEST(ScannerTest, RejectsBadOptions) {
  const auto sphere = make_phantom("sphere", {8, 8, 8}, 0);
  ScanOptions options;
  options.scale = 0;
  EXPECT_THROW(SimulatedScanner(*sphere, options), std::invalid_argument);
  options.scale = -255;
  EXPECT_THROW(SimulatedScanner(*sphere, options), std::invalid_argument);
  options.scale = std::nan("");
  EXPECT_THROW(SimulatedScanner(*sphere, options), std::invalid_argument);
  options = ScanOptions{};
  options.offset = INFINITY;
  EXPECT_THROW(SimulatedScanner(*sphere, options), std::invalid_argument);
  options = ScanOptions{};
  options.spacing[1] = 0;
  EXPECT_THROW(SimulatedScanner(*sphere, options), std::invalid_argument);
}

}  // namespace
}  // namespace mvox::sim
