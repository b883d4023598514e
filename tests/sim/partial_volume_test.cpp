// Partial-volume edges (Phantom::partial_volume_density, boundary_ramp): the one-voxel ramp, and
// the ramp blurred by a Gaussian point-spread function that `mvox demo` scans with, against a
// numerical convolution.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "phantom.h"
#include "phantom_factory.h"
#include "simulated_scanner.h"

namespace mvox::sim {
namespace {

TEST(PartialVolume, WithoutBlurTheRampIsOneVoxelWide) {
  EXPECT_EQ(boundary_ramp(-0.5, 0.0), 0.0f);
  EXPECT_EQ(boundary_ramp(-0.25, 0.0), 0.25f);
  EXPECT_EQ(boundary_ramp(0.0, 0.0), 0.5f);
  EXPECT_EQ(boundary_ramp(0.25, 0.0), 0.75f);
  EXPECT_EQ(boundary_ramp(0.5, 0.0), 1.0f);
  EXPECT_EQ(boundary_ramp(3.0, 0.0), 1.0f);
}

// The one-voxel ramp convolved with a Gaussian of `sigma`, by Simpson's rule.
double convolved_numerically(double inside, double sigma) {
  const int steps = 4000;
  const double reach = 8.0 * sigma, h = 2.0 * reach / steps;
  double sum = 0;
  for (int i = 0; i <= steps; ++i) {
    const double t = -reach + i * h;
    const double weight = (i == 0 || i == steps) ? 1 : (i % 2 ? 4 : 2);
    const double ramp = std::min(1.0, std::max(0.0, inside - t + 0.5));
    sum += weight * ramp * std::exp(-0.5 * t * t / (sigma * sigma));
  }
  return sum * h / 3.0 / (sigma * std::sqrt(2.0 * 3.14159265358979323846));
}

TEST(PartialVolume, TheBlurredRampIsTheConvolutionHalfOnTheBoundaryAndSymmetric) {
  for (const double sigma : {0.3, 1.0, 2.5}) {
    SCOPED_TRACE("sigma " + std::to_string(sigma));
    EXPECT_FLOAT_EQ(boundary_ramp(0.0, sigma), 0.5f);
    float previous = -1.0f;
    for (double inside = -boundary_reach(sigma) - 1; inside <= boundary_reach(sigma) + 1;
         inside += 0.05) {
      const float value = boundary_ramp(inside, sigma);
      EXPECT_NEAR(value, convolved_numerically(inside, sigma), 1e-6) << "at " << inside;
      EXPECT_NEAR(value + boundary_ramp(-inside, sigma), 1.0f, 1e-6f) << "at " << inside;
      EXPECT_GE(value, previous) << "at " << inside;
      previous = value;
    }
  }
}

TEST(PartialVolume, BlurredSheppLoganKeepsItsLevelsAwayFromEdges) {
  // Voxel (64, 64, 96) of 128^3 lies in the brain at least 14 voxels from every ellipsoid's
  // surface: it reads the brain's 0.2 whatever the blur, up to a blur that reaches it.
  const auto phantom = make_phantom("shepp-logan", {128, 128, 128}, 1);
  EXPECT_NEAR(phantom->density(64, 64, 96), 0.2f, 1e-6f);
  for (const double sigma : {0.0, 1.0, 2.0})
    EXPECT_NEAR(phantom->partial_volume_density(64, 64, 96, sigma), 0.2f, 1e-6f) << sigma;
  EXPECT_GT(std::fabs(phantom->partial_volume_density(64, 64, 96, 6.0) - 0.2f), 1e-3f)
      << "a blur of 6 voxels is felt there";
}

TEST(PartialVolume, TheScannerRefusesANegativeOrUndefinedBlur) {
  const auto sphere = make_phantom("sphere", {8, 8, 8}, 0);
  ScanOptions options;
  options.partial_volume = true;
  options.psf_sigma = -1;
  EXPECT_THROW(SimulatedScanner(*sphere, options), std::invalid_argument);
  options.psf_sigma = std::nan("");
  EXPECT_THROW(SimulatedScanner(*sphere, options), std::invalid_argument);
  options.psf_sigma = 1;
  EXPECT_NO_THROW(SimulatedScanner(*sphere, options));
}

}  // namespace
}  // namespace mvox::sim
