// A run's memory, known before reading (src/pipeline/memory_plan.h): sizes as users write and read
// them, the default budget, --dry-run (the plan, no slice read, nothing written), --max-memory (a
// run over it refused up front), the plan against the memory a run really took, and running out of
// memory anyway (one line, not "std::bad_alloc").
#include "pipeline/memory_plan.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "command_runner.h"
#include "error.h"
#include "file_io.h"
#include "pipeline/slab_extraction.h"
#include "refusal.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::run_mvox;
using test::ScratchDirectory;

TEST(MemorySize, ReadsWhatUsersWrite) {
  EXPECT_EQ(parse_memory_size("64M"), std::uint64_t{64} << 20);
  EXPECT_EQ(parse_memory_size("64MiB"), std::uint64_t{64} << 20);
  EXPECT_EQ(parse_memory_size("64mb"), std::uint64_t{64} << 20);
  EXPECT_EQ(parse_memory_size("2G"), std::uint64_t{2} << 30);
  EXPECT_EQ(parse_memory_size("1.5G"), std::uint64_t{3} << 29);
  EXPECT_EQ(parse_memory_size("512k"), std::uint64_t{512} << 10);
  EXPECT_EQ(parse_memory_size("1T"), std::uint64_t{1} << 40);
  EXPECT_EQ(parse_memory_size("100000"), 100000u);
  EXPECT_EQ(parse_memory_size("100000B"), 100000u);
  EXPECT_EQ(parse_memory_size("none"), 0u);
  EXPECT_EQ(parse_memory_size("0"), 0u);
  for (const char* bad :
       {"", "M", "-1G", "1X", "1GG", "G1", "1e400", "9999999T", "nan", "inf", " 1G"})
    EXPECT_FALSE(parse_memory_size(bad).has_value()) << bad;
}

TEST(MemorySize, IsShownInBinaryUnits) {
  EXPECT_EQ(memory_text(512), "512 B");
  EXPECT_EQ(memory_text(218 * 1024), "218 KiB");
  EXPECT_EQ(memory_text(1363148), "1.3 MiB");
  EXPECT_EQ(memory_text(std::uint64_t{4} << 30), "4.0 GiB");
}

TEST(MemoryBudget, DefaultsToAtMostThePhysicalMemory) {
  const MemoryBudget budget = default_memory_budget();
  const std::uint64_t physical = static_cast<std::uint64_t>(sysconf(_SC_PHYS_PAGES)) *
                                 static_cast<std::uint64_t>(sysconf(_SC_PAGESIZE));
  EXPECT_GT(budget.bytes, 0u);
  EXPECT_LE(budget.bytes, physical);
  EXPECT_FALSE(budget.source.empty());
}

TEST(MemoryBudget, AnOverBudgetPlanIsRefusedNamingTheInputTheNeedAndTheBudget) {
  MemoryPlan plan;
  plan.process_bytes = 50 << 20;
  plan.add("engine workspace", 1 << 20);
  plan.add("reader (slice and decoder buffers)", std::uint64_t{4} << 30);
  check_memory_budget(plan, MemoryBudget{0, "none"}, "scan.nrrd");  // no limit
  check_memory_budget(plan, MemoryBudget{std::uint64_t{5} << 30, "--max-memory 5G"}, "scan.nrrd");
  try {
    check_memory_budget(plan, MemoryBudget{64 << 20, "--max-memory 64M"}, "scan.nrrd");
    ADD_FAILURE() << "not refused";
  } catch (const Error& error) {
    EXPECT_EQ(error.subject(), "scan.nrrd");
    EXPECT_EQ(error.problem().rfind("needs 4.0 GiB (reader (slice and decoder buffers) 4.0 GiB, "
                                    "engine workspace 1.0 MiB, ...; 50 MiB of it the program "
                                    "and its libraries), over the --max-memory 64M budget of 64 "
                                    "MiB",
                                    0),
              0u)
        << error.problem();
  }
}

// A raw volume of random 16-bit samples: big slices dominate the run's memory, and a random
// surface fills the mesh writer's buffers.
class MemoryPlanCli : public ::testing::Test {
 protected:
  void SetUp() override {
    std::mt19937 random(7);
    std::string samples(std::size_t{1024} * 1024 * 2 * 6, '\0');
    for (char& c : samples) c = static_cast<char>(random());
    std::ofstream(dir_.path() / "volume.raw", std::ios::binary) << samples;
    ASSERT_EQ(run_mvox("phantom sphere -o stack --size 12x10x8 -q", dir_.path()).exit_code, 0);
  }
  std::string read(const std::string& name) {
    std::ifstream in(dir_.path() / name);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }
  // The value of `"key": N` in a JSON text.
  static double number_after(const std::string& json, const std::string& key) {
    const std::size_t at = json.find("\"" + key + "\": ");
    return at == std::string::npos ? -1 : std::stod(json.substr(at + key.size() + 4));
  }
  ScratchDirectory dir_;
};

const std::string kVolume = "extract volume.raw --raw 1024x1024x6:u16le -t 50000";

// What the plan promises is what the run takes: never more (the plan is an upper bound, so a
// budget holds), and not grossly less (so the plan is worth reading). Slices of 2 MiB dominate.
TEST_F(MemoryPlanCli, ThePlanBoundsTheMemoryTheRunTook) {
  // The last two cut the 6 slices into two slabs extracted by two workers (three asked for: at
  // most one per slab): the plan then counts each worker's reader, workspace and recorded
  // output.
  for (const std::string outputs :
       {" -o mesh.ply", " -o mesh.ply --image picture.png", " -o mesh.stl",
        " -o mesh.obj --normals", " -o mesh.ply --threads 2 --slab-slices 4",
        " -o mesh.obj --normals --threads 3 --slab-slices 4",
        " -o mesh.stl --threads 2 --slab-slices 4"}) {
    SCOPED_TRACE(outputs);
    const auto result = run_mvox(kVolume + outputs + " --stats report.json -q", dir_.path());
    ASSERT_EQ(result.exit_code, 0) << result.output;
    const std::string json = read("report.json");
    const double planned = number_after(json, "job_bytes");
    const double measured = number_after(json, "job_memory_bytes");
    ASSERT_GT(planned, 0) << json;
    EXPECT_LE(measured, planned * 1.02 + (1 << 20)) << json;
    const bool slabs = outputs.find("--threads") != std::string::npos;
    // The plan counts every worker's chunks of recorded output, as many as it may grow to (up
    // to 1.5 MiB each); a worker takes more than its first four only when it gets that far
    // ahead of the writer, which depends on how the threads run, so those are left out of what
    // the run must come near. In these two-slab runs the first slab's
    // worker has the turn to write throughout and records nothing (slab_write_turns.h), so half
    // the first chunks are never touched either. STL's chunks also have room for a polygon batch
    // of seven-gons, five triangles each, which a real surface does not come near.
    const std::string recorded = "output recorded ahead of the writer (4 to ";
    const std::size_t recorded_at = json.find(recorded);
    ASSERT_EQ(recorded_at != std::string::npos, slabs) << json;
    const double most_chunks =
        slabs ? std::stod(json.substr(recorded_at + recorded.size())) : kChunksPerWorker;
    const double recorded_bytes = slabs ? number_after(json.substr(recorded_at), "bytes") : 0;
    // 1024x1024 slabs of 4 slices: a worker may hold 8 chunks, about a slab's output (when the
    // budget leaves room: a small container's may not).
    if (slabs && number_after(json, "budget_bytes") > (1 << 30)) EXPECT_EQ(most_chunks, 8) << json;
    const double grown = recorded_bytes * (most_chunks - kChunksPerWorker) / most_chunks;
    const bool stl = outputs.find(".stl") != std::string::npos;
    EXPECT_GE(measured, (planned - grown) * (slabs ? (stl ? 0.3 : 0.4) : 0.6)) << json;
    EXPECT_NE(json.find(slabs ? " slab workers (workspace, slices, window)"
                              : "\"memory_plan\": {\"parts\": [{\"name\": \"engine workspace\""),
              std::string::npos)
        << json;
  }
}

TEST_F(MemoryPlanCli, DryRunPrintsThePlanReadsNoSliceAndWritesNothing) {
  // Every slice after the first is garbage: a real run fails at slice 2, a dry run never gets
  // there (the first slice's header is all it reads).
  for (int z = 1; z < 8; ++z)
    std::ofstream(dir_.path() / ("stack/sphere_000" + std::to_string(z) + ".png")) << "garbage";
  const auto before = test::tree_snapshot(dir_.path());
  const auto dry =
      run_mvox("extract stack -t 128 -o m.ply --image p.png --stats r.json --dry-run", dir_.path());
  EXPECT_EQ(dry.exit_code, 0) << dry.output;
  for (const char* line :
       {"12x10x8 u8 voxels", "engine workspace", "reader (slice and decoder", "reading ahead",
        "slice window", "picture (z-buffer", "mesh writer", "program and libraries", "total",
        "budget: ", "nothing read but headers"})
    EXPECT_NE(dry.output.find(line), std::string::npos) << line << " in:\n" << dry.output;
  test::expect_same_tree(before, test::tree_snapshot(dir_.path()));
  // The checks of a real run come first: a dry run refuses what the run would refuse.
  test::expect_refused(dir_.path(),
                       "extract stack -t 128 -o stack/sphere_0000.png --format ply --dry-run",
                       "stack/sphere_0000.png", "is an input file", 2);
  test::expect_refused(dir_.path(), "extract stack -t 128 -o m.ply --dry-run --max-memory 1M",
                       "stack", "over the --max-memory 1M budget of 1.0 MiB");
}

// Slab workers may take more chunks for the output they keep for their turn, but only as many
// as the budget leaves room for: a run that fits with the first four is never refused for the
// others, and the plan, which bounds the run, stays within the budget.
TEST_F(MemoryPlanCli, WorkersGrowTheirRecordedOutputOnlyAsFarAsTheBudgetLeavesRoom) {
  const std::string run =
      kVolume + " -o mesh.ply --threads 2 --slab-slices 4 -q --stats report.json";
  const std::string recorded = "output recorded ahead of the writer (4 to ";
  auto chunks_of = [&](const std::string& json) {
    const std::size_t at = json.find(recorded);
    return at == std::string::npos ? -1.0 : std::stod(json.substr(at + recorded.size()));
  };
  const auto unbounded = run_mvox(run + " --max-memory none", dir_.path());
  ASSERT_EQ(unbounded.exit_code, 0) << unbounded.output;
  const std::string free_json = read("report.json");
  ASSERT_EQ(chunks_of(free_json), 8) << free_json;  // 1024x1024x4 voxels a slab
  const double total = number_after(free_json, "total_bytes");
  const double one_chunk_each =
      number_after(free_json.substr(free_json.find(recorded)), "bytes") / 8;
  // A budget of what the plan takes with 8 chunks a worker leaves room for 4 more each, and the
  // workers grow into half of it: 6.
  const auto budget = static_cast<std::uint64_t>(total);
  const auto bounded = run_mvox(run + " --max-memory " + std::to_string(budget), dir_.path());
  ASSERT_EQ(bounded.exit_code, 0) << bounded.output;
  const std::string json = read("report.json");
  const double chunks = chunks_of(json);
  // The program's own memory when the plan is made moves a little from run to run.
  EXPECT_GE(chunks, 5) << json;
  EXPECT_LE(chunks, 7) << json;
  EXPECT_LE(number_after(json, "total_bytes"), budget) << json;
  EXPECT_LE(number_after(json, "slab_chunks_taken"), chunks) << json;  // the run kept to it
  const auto one = run_mvox(kVolume + " -o one.ply --threads 1 -q", dir_.path());
  ASSERT_EQ(one.exit_code, 0) << one.output;
  EXPECT_TRUE(test::read_bytes(dir_.path() / "mesh.ply") ==
              test::read_bytes(dir_.path() / "one.ply"));
}

TEST_F(MemoryPlanCli, MaxMemoryRefusesUpFrontOrLetsTheRunGoOn) {
  test::expect_refused(dir_.path(), kVolume + " -o mesh.ply --image p.png --max-memory 20M",
                       "volume.raw", "over the --max-memory 20M budget of 20 MiB");
  const auto result = run_mvox(kVolume + " -o mesh.ply --max-memory 2G -q", dir_.path());
  EXPECT_EQ(result.exit_code, 0) << result.output;
  const auto none = run_mvox(kVolume + " -o mesh2.ply --max-memory none -q", dir_.path());
  EXPECT_EQ(none.exit_code, 0) << none.output;
  test::expect_refused(dir_.path(), kVolume + " -o mesh.ply --max-memory 12Q", "--max-memory",
                       "is not a memory size", 2);
  // 0 is no limit inside; typed, it ran unlimited where it asked for nothing.
  for (const char* zero : {"0", "0M", "0.0G"})
    test::expect_refused(dir_.path(), kVolume + " -o mesh.ply --max-memory " + zero, "--max-memory",
                         "is no memory at all: give a size, or none for no limit", 2);
}

// The default budget follows the address-space limit, as containers and ulimit set it.
TEST_F(MemoryPlanCli, TheDefaultBudgetFollowsUlimit) {
  const auto result = run_mvox(kVolume + " -o mesh.ply --image p.png --dry-run", dir_.path(),
                               "ulimit -v 20000000;");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("(the address-space limit (ulimit -v)): fits"), std::string::npos)
      << result.output;
}

// With no budget and too little memory, an allocation fails mid-run: one line naming the input
// and the size, never "std::bad_alloc". The limit that lets mvox start but not finish depends on
// the machine's libraries, so several are tried; each must give one clean line.
TEST_F(MemoryPlanCli, RunningOutOfMemoryIsOneLineNamingTheInputAndTheSize) {
  const fs::path large = dir_.path() / "large.raw";
  { std::ofstream create(large, std::ios::binary); }
  fs::resize_file(large, std::uint64_t{4000} * 4000 * 2 * 3);  // 32 MiB slices, sparse
  int out_of_memory = 0;
  for (int limit_mib = 150; limit_mib <= 600; limit_mib += 50) {
    const auto result = run_mvox(
        "extract large.raw --raw 4000x4000x3:u16le -t 1 -o m.ply "
        "--image p.png --max-memory none -q",
        dir_.path(), "ulimit -v " + std::to_string(limit_mib * 1024) + ";");
    if (result.output.rfind("mvox: error: ", 0) != 0) continue;  // could not even start
    SCOPED_TRACE(limit_mib);
    test::expect_one_line_error(result, "large.raw");
    EXPECT_EQ(result.output.find("bad_alloc"), std::string::npos) << result.output;
    out_of_memory += result.output.find("out of memory") != std::string::npos;
    EXPECT_FALSE(fs::exists(dir_.path() / "m.ply"));
  }
  EXPECT_GT(out_of_memory, 0) << "no limit made the run fail for lack of memory";
}

}  // namespace
}  // namespace mvox
