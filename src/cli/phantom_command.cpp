// mvox phantom NAME -o DIR: writes a phantom of sim/ as an image stack, so that everything a user
// does with scanned slices can be tried, and tested, on data with known answers.
#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <regex>

#include "cli/commands.h"
#include "cli/option_validators.h"
#include "error.h"
#include "message_line.h"
#include "phantom_factory.h"
#include "pipeline/termination.h"
#include "simulated_scanner.h"
#include "write/slice_image_writer.h"

namespace mvox {
namespace {

struct PhantomArguments {
  std::string name;
  std::string directory;
  std::string size = "64x64x64";
  int bits = 8;
  std::string format = "png";
  std::uint64_t seed = 1;
  bool quiet = false;
};

// The stack's folder while it is written, recorded so that an interrupt removes it too
// (termination.h): removed with everything in it unless published.
struct StagingDirectory {
  std::filesystem::path path;
  int id = 0;
  ~StagingDirectory() {
    if (id != 0) discard_output(id);
  }
};

sim::Grid parse_size(const std::string& text) {
  static const std::regex pattern(R"((\d{1,5})x(\d{1,5})x(\d{1,5}))");
  std::smatch match;
  if (!std::regex_match(text, match, pattern))
    throw UsageError("--size", "'" + text + "' is not WxHxD, for example 64x48x32");
  const sim::Grid grid{static_cast<std::uint32_t>(std::stoul(match[1])),
                       static_cast<std::uint32_t>(std::stoul(match[2])),
                       static_cast<std::uint32_t>(std::stoul(match[3]))};
  if (grid.width == 0 || grid.height == 0 || grid.depth == 0)
    throw UsageError("--size", "'" + text + "' has a zero dimension");
  return grid;
}

void run_phantom(const PhantomArguments& args) {
  const sim::Grid grid = parse_size(args.size);
  const auto phantom = sim::make_phantom(args.name, grid, args.seed);
  const sim::ScanOptions scan =
      sim::default_scan_options(args.bits == 16 ? SampleType::u16 : SampleType::u8);
  sim::SimulatedScanner scanner(*phantom, scan);

  // The stack appears whole or not at all: written into a temporary folder beside the target,
  // renamed into place at the end. An existing non-empty folder is refused, since mixing two
  // stacks would silently make a third volume.
  const std::filesystem::path target(args.directory);
  std::error_code error;
  if (std::filesystem::exists(target, error) && !std::filesystem::is_empty(target, error))
    throw Error(args.directory, "already exists and is not empty; choose a new directory");
  const std::filesystem::path parent =
      target.has_parent_path() ? target.parent_path() : std::filesystem::path(".");
  std::string pattern = (parent / ("." + target.filename().string() + ".XXXXXX")).string();
  StagingDirectory staging;
  if (!create_output_temporary_directory(pattern.data(), args.directory, &staging.id))
    throw Error(args.directory, "cannot create directory: " + errno_text(errno));
  staging.path = pattern;

  SliceView slice;
  for (std::uint32_t z = 0; scanner.next_slice(&slice); ++z) {
    char name[64];
    std::snprintf(name, sizeof name, "%s_%04u.%s", args.name.c_str(), z, args.format.c_str());
    try {
      write_slice_image((staging.path / name).string(), slice);
    } catch (const Error& error) {
      // Named as the user will look for it: the staging folder is gone once this unwinds.
      throw Error((target / name).string(), error.problem());
    }
  }
  // mkdtemp makes the folder 0700; the finished stack gets the usual 0777 & ~umask, as mkdir
  // would give it (umask can only be read by setting it).
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::chmod(staging.path.c_str(), 0777 & ~mask);
  // rename() also replaces an empty directory left at the target.
  if (const int error = publish_output_temporary(staging.id, target.string()))
    throw Error(args.directory, "cannot create directory: " + errno_text(error));
  staging.id = 0;
  if (!args.quiet) {
    const double threshold = sim::sample_threshold(sim::default_density_threshold(args.name), scan);
    std::fprintf(
        stderr,
        "wrote %u slices of %ux%u %d-bit %s to %s\nextract with: mvox extract %s -t %g -o %s.ply\n",
        grid.depth, grid.width, grid.height, args.bits, args.format.c_str(),
        one_line(args.directory).c_str(), one_line(args.directory).c_str(), threshold,
        args.name.c_str());
  }
}

}  // namespace

void add_phantom_command(CLI::App& app) {
  auto args = std::make_shared<PhantomArguments>();
  CLI::App* command = app.add_subcommand(
      "phantom", "Write a simulated phantom as an image stack (test data with known answers)");
  command->add_option("NAME", args->name, "Phantom")
      ->required()
      ->check(CLI::IsMember(sim::phantom_names()));
  command->add_option("-o,--output", args->directory, "Directory for the slices")->required();
  command->add_option("--size", args->size, "WxHxD voxels")->capture_default_str();
  command->add_option("--bits", args->bits, "Bits per sample")
      ->check(CLI::IsMember({8, 16}))
      ->capture_default_str();
  command->add_option("--format", args->format, "Image format")
      ->check(CLI::IsMember({"png", "tif", "pgm"}))
      ->capture_default_str();
  command->add_option("--seed", args->seed, "Seed for the random phantoms")
      ->transform(whole_number_from(0, std::numeric_limits<std::uint64_t>::max()))
      ->capture_default_str();
  command->add_flag("-q,--quiet", args->quiet, "Print nothing");
  command->callback([args] { run_phantom(*args); });
}

}  // namespace mvox
