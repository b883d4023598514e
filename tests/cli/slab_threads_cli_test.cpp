// `mvox extract --threads N`: slabs of slices extracted in parallel give the file one thread
// writes, byte for byte, in every format and option, for N = 1, 2, 3 and 8, on volumes whose
// slab boundaries the surface crosses everywhere (noise), with --stats counting the same; and a
// reading error in the middle of a slab-parallel run fails as a one-thread run does.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "support/command_runner.h"
#include "support/deflate.h"
#include "support/dicom_writer.h"
#include "support/file_io.h"
#include "support/slab_run_checks.h"
#include "support/tiff_bytes.h"

namespace mvox {
namespace {

using test::counters_of;
using test::run_mvox;
using test::write_noise;

TEST(SlabThreads, EveryFormatAndOptionIsTheSameBytesForAnyNumberOfThreads) {
  test::ScratchDirectory dir;
  write_noise(dir / "noise.raw", 41 * 23 * 37, 11);
  const std::string input = "noise.raw --raw 41x23x37:u8 -t 128 -q --slab-slices 4";
  for (const test::MeshCase& c : test::every_format_and_option()) {
    SCOPED_TRACE(std::string(c.extension) + " " + c.options);
    std::string reference, reference_counters;
    for (const int threads : {1, 2, 3, 8}) {
      const std::string mesh = "m" + std::to_string(threads) + "." + c.extension;
      const test::CommandResult result =
          run_mvox("extract " + input + " " + c.options + " -o " + mesh + " --stats s.json" +
                       " --threads " + std::to_string(threads),
                   dir.path());
      ASSERT_EQ(result.exit_code, 0) << result.output;
      const std::string bytes = test::read_bytes(dir.path() / mesh);
      const std::string counters = counters_of(test::read_bytes(dir.path() / "s.json"));
      if (threads == 1) {
        reference = bytes;
        reference_counters = counters;
        EXPECT_GT(bytes.size(), 10000u);
        continue;
      }
      EXPECT_TRUE(bytes == reference) << threads << " threads wrote other bytes";
      EXPECT_EQ(counters, reference_counters);
    }
  }
}

// Each worker draws its slabs into a layer of its own and the layers are composited (sort-last):
// the picture is the one engine's, bit for bit, seen from every side (front to back, where the
// earlier slabs hide the later ones, and back to front), smooth and flat, alone or with a mesh.
TEST(SlabThreads, ThePictureIsTheSameBytesForAnyNumberOfThreads) {
  test::ScratchDirectory dir;
  write_noise(dir / "noise.raw", 41 * 23 * 37, 5);
  const std::string input = "noise.raw --raw 41x23x37:u8 -t 128 -q --slab-slices 4";
  const char* cases[] = {
      "",
      "--view 0 -60",
      "--view 200 -30 --flat",
      "--view 0 89 --image-size 97x61",
      "--method cubes --view 30 20",
      "--cut 0.5 --view 30 20",
      "-o mesh.ply --normals --view 120 10",
  };
  for (const char* options : cases) {
    SCOPED_TRACE(options);
    std::string reference, reference_counters;
    for (const int threads : {1, 2, 3, 8}) {
      const test::CommandResult result =
          run_mvox("extract " + input + " " + options + " --image p.png --stats s.json" +
                       " --threads " + std::to_string(threads),
                   dir.path());
      ASSERT_EQ(result.exit_code, 0) << result.output;
      const std::string picture = test::read_bytes(dir.path() / "p.png");
      const std::string report = test::read_bytes(dir.path() / "s.json");
      if (threads == 1) {
        reference = picture;
        reference_counters = counters_of(report);
        continue;
      }
      EXPECT_NE(report.find(std::to_string(std::min(threads, 10)) + " picture layers"),
                std::string::npos)
          << "not drawn in parallel: " << report;
      EXPECT_TRUE(picture == reference) << threads << " threads drew another picture";
      EXPECT_EQ(counters_of(report), reference_counters);
    }
  }
}

// Threads asked for that the job cannot use are said in one note, naming the option that needs
// one engine; never silently, never twice, never with -q, and not when no --threads was given.
TEST(SlabThreads, ThreadsThatCannotBeUsedAreSaidInANote) {
  test::ScratchDirectory dir;
  write_noise(dir / "noise.raw", 41 * 23 * 37, 5);
  const std::string input = "extract noise.raw --raw 41x23x37:u8 -t 128 --slab-slices 4 ";
  const std::pair<std::string, std::string> cases[] = {
      {"-o m.ply --smooth 2", "--smooth"},
      {"-o m.ply --decimate 0.5", "--decimate"},
      {"-o m.ply --largest", "--largest"},
  };
  for (const auto& [options, option] : cases) {
    SCOPED_TRACE(options);
    const test::CommandResult result = run_mvox(input + options + " --threads 3", dir.path());
    ASSERT_EQ(result.exit_code, 0) << result.output;
    const std::string note = "mvox: note: --threads 3: " + option;
    const std::size_t at = result.output.find(note);
    ASSERT_NE(at, std::string::npos) << result.output;
    EXPECT_EQ(result.output.find(note, at + 1), std::string::npos) << "said twice";
    EXPECT_NE(result.output.find("; one engine extracts\n", at), std::string::npos)
        << result.output;
    EXPECT_EQ(run_mvox(input + options + " --threads 3 -q", dir.path()).output, "");
    EXPECT_EQ(run_mvox(input + options, dir.path()).output.find("note:"), std::string::npos);
  }
  for (const char* options : {"-o m.ply", "--image p.png --frames f"}) {
    const test::CommandResult usable = run_mvox(input + options + " --threads 3", dir.path());
    EXPECT_EQ(usable.output.find("note:"), std::string::npos) << usable.output;
  }
}

// The threads a run starts, as strace sees them: clone calls that make a thread.
int threads_started(const std::string& arguments, const test::ScratchDirectory& dir) {
  const test::CommandResult result =
      run_mvox(arguments, dir.path(), "strace -f -qq -e trace=clone,clone3 -o clones.txt");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  const std::string calls = test::read_bytes(dir.path() / "clones.txt");
  int threads = 0;
  for (std::size_t at = 0; (at = calls.find("CLONE_THREAD", at)) != std::string::npos; ++at)
    ++threads;
  return threads;
}

// --threads 1 is for single-core devices: no reading thread and no writing thread, only the one
// that sleeps until Ctrl-C to remove temporaries; so are slab workers on every core. The mesh here
// is several MiB, so a writer would start its thread, and several batches, so a reading thread
// would have work. Its faces' scratch file (30 MB) is large enough for the runs not limited to
// one thread to free it on a thread of its own at the end (deferred_close.h), one more.
TEST(SlabThreads, OneThreadOrAWorkerPerCoreMeansNoWritingThread) {
  test::ScratchDirectory dir;
  write_noise(dir / "noise.raw", 200 * 150 * 40, 5);
  const std::string run = "extract noise.raw --raw 200x150x40:u8 -t 128 -q -o m.ply";
  EXPECT_EQ(threads_started(run + " --threads 1", dir), 1);
  const std::string one = test::read_bytes(dir.path() / "m.ply");
  ASSERT_GT(one.size(), std::size_t{4} << 20);
  // One slab worker per core (40 slices, 4 a slab): the workers read the file themselves and,
  // with no core left for a writing thread, write on their own threads. On a machine with more
  // cores than slabs the workers leave cores free, and the writer has its thread.
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const unsigned workers = std::min(cores, 10u);
  if (cores >= 2) {
    const int started =
        threads_started(run + " --threads " + std::to_string(cores) + " --slab-slices 4", dir);
    if (workers == cores) {
      EXPECT_EQ(started, 2 + static_cast<int>(workers));
    } else {
      EXPECT_GE(started, 3 + static_cast<int>(workers));
    }
    EXPECT_EQ(test::read_bytes(dir.path() / "m.ply"), one);
  }
  // One engine, the default for a volume this small: raw samples, read by its own thread, and
  // no writing thread either (OneEngineReadsAheadOnlyWhereThereIsWorkToOverlap); only the
  // closing one.
  EXPECT_EQ(threads_started(run, dir), 2);
  EXPECT_EQ(test::read_bytes(dir.path() / "m.ply"), one);
  // Asked for two threads, and given one slab, the engine has a reading thread and the writer
  // its own.
  EXPECT_GE(threads_started(run + " --threads 2 --slab-slices 40", dir), 4);
  EXPECT_EQ(test::read_bytes(dir.path() / "m.ply"), one);
}

// `mvox extract INPUT -o FILE OPTIONS` with 4-slice slabs on 2, 3 and 8 threads writes the
// bytes one thread writes, which must exceed `least_bytes`.
void expect_slabs_keep_the_bytes(const test::ScratchDirectory& dir, const std::string& input,
                                 const std::string& file, const std::string& options,
                                 std::size_t least_bytes) {
  SCOPED_TRACE(file + " " + options);
  const std::string run = "extract " + input + " -t 128 -q -o " + file + " " + options;
  ASSERT_EQ(run_mvox(run + " --threads 1", dir.path()).exit_code, 0);
  const std::string one = test::read_bytes(dir.path() / file);
  ASSERT_GT(one.size(), least_bytes);
  for (const char* threads : {"2", "3", "8"}) {
    SCOPED_TRACE(threads);
    const auto result =
        run_mvox(run + " --slab-slices 4 --threads " + std::string(threads), dir.path());
    ASSERT_EQ(result.exit_code, 0) << result.output;
    EXPECT_TRUE(test::read_bytes(dir.path() / file) == one);
  }
}

// Each 4-slice slab of this noise emits several MiB, more than a worker's chunks hold: a worker
// ahead of the slab being written fills its chunks and waits for its turn, and a worker that
// ends its slab before its turn leaves it recorded for whoever hands the turn on
// (slab_write_turns.h). Any number of workers gives one engine's bytes: PLY, whose workers
// record the engine's batches, and STL, whose workers record their triangles formatted
// (face_formatter.h), the turn often coming in the middle of a slab.
TEST(SlabThreads, SlabsLargerThanTheirChunksWaitForTheirTurnAndKeepTheBytes) {
  test::ScratchDirectory dir;
  write_noise(dir / "noise.raw", 200 * 150 * 40, 9);
  for (const char* mesh : {"m.ply", "m.stl"})
    expect_slabs_keep_the_bytes(dir, "noise.raw --raw 200x150x40:u8", mesh, "",
                                std::size_t{16} << 20);
}

// The text formats' workers record their slabs' vertex lines formatted (vertex_text_formatter.h),
// with normals here, a slab over many 512 KiB chunks (about a third of the file each); the face
// lines are made by the turn's holder.
TEST(SlabThreads, TextSlabsLargerThanTheirChunksKeepTheBytes) {
  test::ScratchDirectory dir;
  write_noise(dir / "noise.raw", 100 * 80 * 12, 5);
  const std::string input = "noise.raw --raw 100x80x12:u8";
  expect_slabs_keep_the_bytes(dir, input, "m.obj", "--normals", std::size_t{8} << 20);
  expect_slabs_keep_the_bytes(dir, input, "m.ply", "--normals --ascii", std::size_t{8} << 20);
}

TEST(SlabThreads, ThePlanShowsTheWorkersAndDoesNotGrowWithDepth) {
  test::ScratchDirectory dir;
  auto plan = [&](const std::string& size) {
    const test::CommandResult result = run_mvox(
        "extract /dev/zero --raw " + size + ":u8 -t 1 -o m.ply --dry-run --threads 2", dir.path());
    EXPECT_EQ(result.exit_code, 0) << result.output;
    const std::size_t at = result.output.find("slab workers");
    EXPECT_NE(at, std::string::npos) << result.output;
    return result.output.substr(at, result.output.find('\n', at) - at);
  };
  EXPECT_EQ(plan("512x512x400"), plan("512x512x40000"));
}

// Without --threads: one worker per core from 64 MiB of samples on, one engine below (where
// starting workers costs about what they save). Sparse files: a dry run reads no slice.
TEST(SlabThreads, TheDefaultIsOneWorkerPerCoreForLargeVolumes) {
  test::ScratchDirectory dir;
  auto dry_run = [&](const std::string& name, std::uint32_t depth) {
    test::write_bytes(dir / name, std::string());
    std::filesystem::resize_file(dir / name, std::uintmax_t{256} * 256 * depth);
    const test::CommandResult result =
        run_mvox("extract " + name + " --raw 256x256x" + std::to_string(depth) +
                     ":u8 -t 1 -o m.ply --dry-run",
                 dir.path());
    EXPECT_EQ(result.exit_code, 0) << result.output;
    return result.output;
  };
  const unsigned cores = std::thread::hardware_concurrency();
  const std::string large = dry_run("large.raw", 1024);  // 64 MiB
  if (cores > 1) {
    EXPECT_NE(large.find(std::to_string(cores) + " slab workers"), std::string::npos) << large;
  } else {
    EXPECT_EQ(large.find("slab workers"), std::string::npos) << large;
  }
  const std::string small = dry_run("small.raw", 1023);
  EXPECT_EQ(small.find("slab workers"), std::string::npos) << small;
  // Raw samples: the one engine reads them itself (see the next test).
  EXPECT_EQ(small.find("reading ahead"), std::string::npos) << small;
}

// One engine takes a reading thread (and its writers one each) by default only where there is
// work to overlap: slices to decode, a pipe to wait on, or a volume of 64 MiB or more. A small
// volume of raw samples read from a file is read by the engine's own thread, and any volume is
// when --threads asks for more than one.
TEST(SlabThreads, OneEngineReadsAheadOnlyWhereThereIsWorkToOverlap) {
  test::ScratchDirectory dir;
  const std::vector<std::uint8_t> noise = test::noise_samples(64 * 48 * 20, 3);
  const std::string samples(noise.begin(), noise.end());
  test::write_bytes(dir / "v.raw", samples);
  test::write_bytes(
      dir / "raw.nrrd",
      "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 64 48 20\nencoding: raw\n\n" + samples);
  const std::vector<unsigned char> bytes(samples.begin(), samples.end());
  const std::vector<unsigned char> gzip = test::deflate_bytes(bytes, true);
  test::write_bytes(dir / "gzip.nrrd",
                    "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 64 48 20\nencoding: gzip\n\n" +
                        std::string(gzip.begin(), gzip.end()));
  for (const bool deflate : {false, true}) {
    const std::vector<unsigned char> tiff =
        test::tiff_file_bytes(test::tiff_pages_of(samples, 64, 48, 0, 20, deflate));
    test::write_bytes(dir / (deflate ? "deflate.tif" : "plain.tif"),
                      std::string(tiff.begin(), tiff.end()));
  }
  ASSERT_EQ(run_mvox("phantom blobs -o stack --size 64x48x20 -q", dir.path()).exit_code, 0);

  auto reads_ahead = [&](const std::string& input, const std::string& prefix = "") {
    const test::CommandResult result =
        run_mvox("extract " + input + " -t 128 -o m.ply --dry-run", dir.path(), prefix);
    EXPECT_EQ(result.exit_code, 0) << result.output;
    return result.output.find("reading ahead") != std::string::npos;
  };
  EXPECT_FALSE(reads_ahead("v.raw --raw 64x48x20:u8"));
  EXPECT_FALSE(reads_ahead("raw.nrrd"));
  EXPECT_FALSE(reads_ahead("plain.tif"));
  EXPECT_TRUE(reads_ahead("gzip.nrrd"));
  EXPECT_TRUE(reads_ahead("deflate.tif"));
  EXPECT_TRUE(reads_ahead("stack"));
  EXPECT_TRUE(reads_ahead("/dev/stdin --raw 64x48x20:u8", "cat v.raw |"));  // a pipe
  EXPECT_FALSE(reads_ahead("/dev/stdin --raw 64x48x20:u8 < v.raw"));        // the file itself
  // Asked for: 20 slices make one slab, so one engine, with its reading thread.
  EXPECT_TRUE(reads_ahead("v.raw --raw 64x48x20:u8 --threads 2"));
  EXPECT_FALSE(reads_ahead("stack --threads 1"));
  // The run does as its plan says: the PNG stack's slices come from a reading thread, the raw
  // file's from the engine's own (beside the thread that waits for Ctrl-C, as ever).
  EXPECT_GE(threads_started("extract stack -t 128 -o m.ply -q", dir), 2);
  EXPECT_EQ(threads_started("extract v.raw --raw 64x48x20:u8 -t 128 -o m.ply -q", dir), 1);
}

// Files are read by each worker for its own slabs (stacks of images or raw slices, a raw volume
// file, NRRD, MetaImage, TIFF stacks, DICOM series); a pipe is read once by one thread and
// fanned out. Both give
// the bytes one thread writes.
TEST(SlabThreads, EveryKindOfInputIsTheSameBytesForAnyNumberOfThreads) {
  test::ScratchDirectory dir;
  ASSERT_EQ(run_mvox("phantom blobs -o stack --size 30x20x33 -q", dir.path()).exit_code, 0);
  write_noise(dir / "noise.raw", 19 * 13 * 29, 3);
  std::filesystem::create_directory(dir / "slices");
  const std::string noise = test::read_bytes(dir / "noise.raw");
  for (int z = 0; z < 29; ++z) {
    char name[32];
    std::snprintf(name, sizeof name, "slices/s%03d.raw", z);
    test::write_bytes(dir / name, noise.substr(std::size_t{19} * 13 * z, 19 * 13));
  }
  // MetaImage and NRRD with raw data: read by each worker for its own slabs too.
  test::write_bytes(dir / "noise.mhd",
                    std::string("ObjectType = Image\nNDims = 3\nDimSize = 19 13 29\n"
                                "ElementType = MET_UCHAR\nElementDataFile = noise.raw\n"));
  test::write_bytes(
      dir / "noise.nrrd",
      "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 19 13 29\nencoding: raw\n\n" + noise);
  // A TIFF stack in two files, uncompressed and deflate: read by each worker too, from the
  // page its range starts at.
  test::write_bytes(dir / "tiff/a.tif",
                    test::tiff_file_bytes(test::tiff_pages_of(noise, 19, 13, 0, 11, false)));
  test::write_bytes(dir / "tiff/b.tif",
                    test::tiff_file_bytes(test::tiff_pages_of(noise, 19, 13, 11, 18, true, 5)));
  // A DICOM series, its slices native and in four compressions, decoded by each worker with a
  // GDCM reader of its own.
  const char* syntaxes[] = {test::kExplicitLittleEndianUid, test::kRleLosslessUid,
                            test::kJpegLosslessUid, test::kJpegLsLosslessUid,
                            test::kJpeg2000LosslessUid};
  test::write_dicom_series(dir / "dicom", noise, 19, 13, 29,
                           [&](std::uint32_t z) { return syntaxes[z % 5]; });
  const std::string inputs[] = {
      "stack -t 100",
      "stack -t 100 --normals",
      "'slices/s*.raw' --raw 19x13:u8 -t 128",
      "noise.raw --raw 19x13x29:u8 -t 128 --normals",
      "noise.mhd -t 128 --normals",
      "noise.nrrd -t 128",
      "tiff -t 128 --normals",
      "dicom -t 128 --normals",
  };
  for (const std::string& input : inputs) {
    for (const bool piped : {false, true}) {
      // A pipe: the same volume through standard input, raw inputs only.
      if (piped && input.rfind("noise.raw", 0) != 0) continue;
      const std::string command = "extract " + (piped ? "/dev/stdin" + input.substr(9) : input) +
                                  " -q --slab-slices 4 -o m.ply --threads ";
      SCOPED_TRACE(command + (piped ? " (piped)" : ""));
      std::string reference;
      for (const int threads : {1, 2, 3, 8}) {
        const test::CommandResult result =
            run_mvox(command + std::to_string(threads), dir.path(), piped ? "cat noise.raw |" : "");
        ASSERT_EQ(result.exit_code, 0) << result.output;
        const std::string bytes = test::read_bytes(dir.path() / "m.ply");
        if (threads == 1) reference = bytes;
        EXPECT_GT(bytes.size(), 1000u);
        EXPECT_TRUE(bytes == reference) << threads << " threads wrote other bytes";
      }
    }
  }
}

// "-" is standard input, as pipelines write it: a raw volume piped in is read once and fanned
// out to the workers, as from /dev/stdin. A terminal there is refused before anything is read,
// and a file that is really named "-" is still that file.
TEST(SlabThreads, ADashIsStandardInput) {
  test::ScratchDirectory dir;
  write_noise(dir / "noise.raw", 19 * 13 * 29, 4);
  const std::string volume = " --raw 19x13x29:u8 -t 128 -q --slab-slices 4";
  ASSERT_EQ(
      run_mvox("extract noise.raw" + volume + " -o file.ply --threads 1", dir.path()).exit_code, 0);
  const test::CommandResult piped =
      run_mvox("extract -" + volume + " -o piped.ply --threads 3", dir.path(), "cat noise.raw |");
  ASSERT_EQ(piped.exit_code, 0) << piped.output;
  EXPECT_TRUE(test::read_bytes(dir.path() / "piped.ply") ==
              test::read_bytes(dir.path() / "file.ply"));

  // script(1) gives mvox a terminal for its standard input; a build that read it would wait for
  // typing, which timeout ends.
  const test::CommandResult terminal = run_mvox("extract -" + volume + " -o tty.ply\" /dev/null",
                                                dir.path(), "timeout 20 script -qec \"");
  EXPECT_EQ(terminal.exit_code, 2) << terminal.output;
  EXPECT_NE(terminal.output.find("- is standard input, which is a terminal here"),
            std::string::npos)
      << terminal.output;
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "tty.ply"));

  std::filesystem::copy_file(dir.path() / "noise.raw", dir.path() / "-");
  const test::CommandResult named =
      run_mvox("extract -" + volume + " -o named.ply --threads 2 < /dev/null", dir.path());
  ASSERT_EQ(named.exit_code, 0) << named.output;
  EXPECT_TRUE(test::read_bytes(dir.path() / "named.ply") ==
              test::read_bytes(dir.path() / "file.ply"));
}

TEST(SlabThreads, AStackThatFailsMidwayFailsAsWithOneThread) {
  test::ScratchDirectory dir;
  ASSERT_EQ(run_mvox("phantom sphere -o stack --size 24x24x40 -q", dir.path()).exit_code, 0);
  std::vector<std::string> slices;
  for (const auto& entry : std::filesystem::directory_iterator(dir / "stack"))
    slices.push_back(entry.path().filename().string());
  std::sort(slices.begin(), slices.end());
  ASSERT_EQ(slices.size(), 40u);
  // A slice in the third slab of four slices cut short: the PNG reader refuses it.
  const std::string broken = dir / ("stack/" + slices[10]);
  const std::string bytes = test::read_bytes(broken);
  test::write_bytes(broken, bytes.substr(0, bytes.size() / 2));
  const test::CommandResult one =
      run_mvox("extract stack -t 100 -o m.ply -q --threads 1", dir.path());
  const test::CommandResult two =
      run_mvox("extract stack -t 100 -o m.ply -q --threads 2 --slab-slices 4", dir.path());
  test::expect_one_line_error(two, slices[10]);
  EXPECT_EQ(two.output, one.output);
  EXPECT_EQ(two.exit_code, one.exit_code);
  EXPECT_FALSE(test::exists(dir / "m.ply"));

  // Bad slices in three slabs, each worker reading its own: the second slab's worker comes to
  // slice 5 as soon as the first slab's comes to slice 2 (both are their third reads), and
  // either may fail first, yet the error is slice 2's, as one thread reading in order reports.
  test::write_bytes(dir / ("stack/" + slices[2]), "not an image");
  test::write_bytes(dir / ("stack/" + slices[5]), "not an image either");
  const test::CommandResult first =
      run_mvox("extract stack -t 100 -o m.ply -q --threads 1", dir.path());
  test::expect_one_line_error(first, slices[2]);
  for (int run = 0; run < 10; ++run) {
    const test::CommandResult eight =
        run_mvox("extract stack -t 100 -o m.ply -q --threads 8 --slab-slices 4", dir.path());
    EXPECT_EQ(eight.output, first.output);
    EXPECT_EQ(eight.exit_code, first.exit_code);
  }
  EXPECT_FALSE(test::exists(dir / "m.ply"));
}

}  // namespace
}  // namespace mvox
