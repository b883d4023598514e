#pragma once
// Which kinds of file a reader takes when it opens a path (file_bytes.h, raw_file.h).
namespace mvox {

// any: whatever the path names; a FIFO is opened as it comes, waiting for its writer (a volume
// piped in). only_regular: a file listed as a regular file and opened again at its turn (a
// slice of a stack), refused with "is no longer a regular file" when it is not one now, without
// waiting for the writer of a FIFO put in its place.
enum class FileKinds { any, only_regular };

}  // namespace mvox
