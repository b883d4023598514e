// Listing the input files (src/read/input_files.h): a directory's slice images or raw slices in
// natural order, globs and explicit files sorted, refusals that name the input, and entries named
// like slices that are no files refused rather than skipped.
#include "read/input_files.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "command_runner.h"
#include "error_capture.h"
#include "file_io.h"

namespace fs = std::filesystem;

namespace mvox {
namespace {

using test::error_of;
using test::ScratchDirectory;
using test::touch;

TEST(InputFiles, DirectoryKeepsSliceImagesInNaturalOrder) {
  ScratchDirectory dir;
  for (const char* name : {"slice10.png", "slice2.PNG", "slice1.tif", "slice3.JpEg", ".hidden.png",
                           "notes.txt", "noextension", "sub/slice4.png"}) {
    touch(dir / name);
  }
  EXPECT_EQ(list_input_files({dir.str()}, InputKind::image_stack),
            (std::vector<std::string>{dir / "slice1.tif", dir / "slice2.PNG", dir / "slice3.JpEg",
                                      dir / "slice10.png"}));
  EXPECT_EQ(
      list_input_files({dir.str()}, InputKind::raw_files),
      (std::vector<std::string>{dir / "noextension", dir / "notes.txt", dir / "slice1.tif",
                                dir / "slice2.PNG", dir / "slice3.JpEg", dir / "slice10.png"}));
}

TEST(InputFiles, GlobAndExplicitFilesAreSortedNaturally) {
  ScratchDirectory dir;
  for (const char* name :
       {"CThead.10", "CThead.9", "CThead.1", "CThead.100", "CThead.2", "desc.txt"}) {
    touch(dir / name);
  }
  EXPECT_EQ(list_input_files({dir / "CThead.*"}, InputKind::raw_files),
            (std::vector<std::string>{dir / "CThead.1", dir / "CThead.2", dir / "CThead.9",
                                      dir / "CThead.10", dir / "CThead.100"}));
  EXPECT_EQ(list_input_files({dir / "CThead.10", dir / "CThead.9", dir / "CThead.2"},
                             InputKind::image_stack),
            (std::vector<std::string>{dir / "CThead.2", dir / "CThead.9", dir / "CThead.10"}));
}

TEST(InputFiles, RefusalsNameTheInput) {
  ScratchDirectory dir;
  fs::create_directories(dir / "empty");
  fs::create_directories(dir / "only_hidden");
  touch(dir / "only_hidden/.slice1.png");
  touch(dir / "no_images/readme.txt");
  touch(dir / "no_images/CThead.1");

  EXPECT_CONTAINS(error_of([&] { list_input_files({dir / "missing"}, InputKind::image_stack); }),
                  dir / "missing");
  EXPECT_CONTAINS(error_of([&] { list_input_files({dir / "nope*.png"}, InputKind::image_stack); }),
                  dir / "nope*.png");
  EXPECT_CONTAINS(error_of([&] { list_input_files({dir / "empty"}, InputKind::raw_files); }),
                  dir / "empty");
  EXPECT_CONTAINS(error_of([&] { list_input_files({dir / "only_hidden"}, InputKind::raw_files); }),
                  dir / "only_hidden");
  const std::string no_images =
      error_of([&] { list_input_files({dir / "no_images"}, InputKind::image_stack); });
  EXPECT_CONTAINS(no_images, dir / "no_images");
  EXPECT_CONTAINS(no_images, "png");
  // The same directory is fine for raw slices.
  EXPECT_EQ(list_input_files({dir / "no_images"}, InputKind::raw_files).size(), 2u);
  EXPECT_CONTAINS(error_of([] { list_input_files({}, InputKind::image_stack); }), "INPUT");
}

TEST(InputFiles, EntriesNamedLikeSlicesThatAreNoFilesAreRefusedNotSkipped) {
  ScratchDirectory dir;
  touch(dir / "stack/s1.png");
  touch(dir / "stack/s3.png");
  fs::create_directories(dir / "stack/notes");  // no slice name: skipped
  EXPECT_EQ(list_input_files({dir / "stack"}, InputKind::image_stack).size(), 2u);
  // Skipping these would close the gap of a lost slice without a word.
  fs::create_symlink(dir / "gone.png", dir / "stack/s2.png");
  EXPECT_CONTAINS(error_of([&] { list_input_files({dir / "stack"}, InputKind::image_stack); }),
                  dir / "stack/s2.png: is a dangling symbolic link");
  EXPECT_CONTAINS(
      error_of([&] { list_input_files({dir / "stack/s*.png"}, InputKind::image_stack); }),
      dir / "stack/s2.png: is a dangling symbolic link");
  fs::remove(dir / "stack/s2.png");
  fs::create_directories(dir / "stack/s2.png");
  EXPECT_CONTAINS(error_of([&] { list_input_files({dir / "stack"}, InputKind::image_stack); }),
                  dir / "stack/s2.png: is a directory");
  // Raw slices have no extension: any dangling name counts, a directory is skipped.
  touch(dir / "raw/CThead.1");
  fs::create_directories(dir / "raw/CThead.2");
  EXPECT_EQ(list_input_files({dir / "raw"}, InputKind::raw_files).size(), 1u);
  fs::create_symlink(dir / "gone", dir / "raw/CThead.3");
  EXPECT_CONTAINS(error_of([&] { list_input_files({dir / "raw"}, InputKind::raw_files); }),
                  dir / "raw/CThead.3: is a dangling symbolic link");
}

}  // namespace
}  // namespace mvox
