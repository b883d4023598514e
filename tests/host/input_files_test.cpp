// Listing the input files (src/read/input_files.h): a directory's slice images or raw slices in
// natural order, globs and explicit files sorted, refusals that name the input, and entries named
// like slices that are no files refused rather than skipped.
#include "read/input_files.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <string>
#include <vector>

#include "command_runner.h"
#include "error_capture.h"
#include "file_io.h"
#include "read/file_names.h"

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

TEST(InputFiles, FifosAndDirectoriesAreNamedWhereverTheyAreFound) {
  ScratchDirectory dir;
  touch(dir / "stack/s1.png");
  ASSERT_EQ(::mkfifo((dir / "stack/s2.png").c_str(), 0600), 0);
  EXPECT_CONTAINS(error_of([&] { list_input_files({dir / "stack"}, InputKind::image_stack); }),
                  dir / "stack/s2.png: is not a regular file (a FIFO");
  EXPECT_CONTAINS(error_of([&] { list_input_files({dir / "stack/s*.png"}, InputKind::raw_files); }),
                  dir / "stack/s2.png: is not a regular file (a FIFO");
  // Named by the user, a FIFO is taken as given (a stream of raw slices, say).
  EXPECT_EQ(list_input_files({dir / "stack/s2.png"}, InputKind::raw_files),
            (std::vector<std::string>{dir / "stack/s2.png"}));
  // A pattern matching only a directory named like a slice: refused for images, and for raw
  // slices (where a directory is skipped) a pattern without a match.
  fs::create_directories(dir / "dirs/d1.png");
  EXPECT_CONTAINS(error_of([&] { list_input_files({dir / "dirs/d*"}, InputKind::image_stack); }),
                  dir / "dirs/d1.png: is a directory, not a slice image");
  EXPECT_CONTAINS(error_of([&] { list_input_files({dir / "dirs/d*"}, InputKind::raw_files); }),
                  dir / "dirs/d*: no file matches this pattern");
  // Within one directory, an entry's problem comes before the directory's.
  fs::create_directories(dir / "lost");
  touch(dir / "lost/notes.txt");
  fs::create_symlink(dir / "gone.png", dir / "lost/s1.png");
  EXPECT_CONTAINS(error_of([&] { list_input_files({dir / "lost"}, InputKind::image_stack); }),
                  dir / "lost/s1.png: is a dangling symbolic link");
  EXPECT_CONTAINS(
      error_of([&] { list_input_files({dir / "lost"}, InputKind::image_stack, BadEntries::skip); }),
      dir / "lost: directory has no slice images");
}

TEST(InputFiles, OneScanAnswersEveryListingWithoutLookingAgain) {
  ScratchDirectory dir;
  for (const char* name : {"s1.png", "s2.png", "s10.png", "notes.txt"})
    touch(dir / (std::string("stack/") + name));
  const InputScan scan({dir / "stack", dir / "stack/s*.png"});
  // The files are gone, but the scan made before answers for them: the listings a run asks for
  // (DICOM detection, the headered formats, the reader) cost the file system nothing more.
  fs::remove_all(dir / "stack");
  const std::vector<std::string> images = {dir / "stack/s1.png",  dir / "stack/s1.png",
                                           dir / "stack/s2.png",  dir / "stack/s2.png",
                                           dir / "stack/s10.png", dir / "stack/s10.png"};
  EXPECT_EQ(scan.files(InputKind::image_stack, BadEntries::refuse), images);
  std::vector<std::string> raw = images;
  raw.insert(raw.begin(), dir / "stack/notes.txt");  // raw slices take every name of the folder
  EXPECT_EQ(scan.files(InputKind::raw_files, BadEntries::skip), raw);
}

TEST(InputFiles, ReportsTheFirstProblemInTheOrderOfTheArguments) {
  ScratchDirectory dir;
  touch(dir / "a/s1.png");
  fs::create_symlink(dir / "gone.png", dir / "a/s2.png");
  touch(dir / "b/s1.png");
  const InputScan scan({dir / "b/s*.png", dir / "missing", dir / "a"});
  EXPECT_CONTAINS(error_of([&] { scan.files(InputKind::image_stack, BadEntries::refuse); }),
                  dir / "missing: no such file or directory");
  const InputScan later({dir / "b", dir / "a", dir / "missing"});
  EXPECT_CONTAINS(error_of([&] { later.files(InputKind::image_stack, BadEntries::refuse); }),
                  dir / "a/s2.png: is a dangling symbolic link");
  // Skipping the bad entry leaves the missing input to be reported.
  EXPECT_CONTAINS(error_of([&] { later.files(InputKind::image_stack, BadEntries::skip); }),
                  dir / "missing: no such file or directory");
}

TEST(FileNames, AgreeWithStdFilesystem) {
  // The listing cuts names from strings instead of building path objects; it must cut them
  // where std::filesystem does.
  for (const std::string path :
       {"a.png", "dir/slice.PNG", "/abs/dir/s.TiFf", "noext", "dir/", "dir.d/noext", ".hidden",
        "dir/.hidden.png", "..", ".", "dir/..", "a.", "a..png", "..png", "x.nii.gz", "", "/",
        "a/b/c.jpeg", "dir.png/"}) {
    SCOPED_TRACE(path);
    EXPECT_EQ(file_name_of(path), fs::path(path).filename().string());
    std::string expected = fs::path(path).extension().string();
    for (char& c : expected) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    EXPECT_EQ(lowercase_extension(path), expected);
  }
}

}  // namespace
}  // namespace mvox
