#pragma once
// A path's last component and its extension, as std::filesystem::path's filename() and
// extension() give them, cut from the string directly. Listing a stack asks these of every
// slice file several times (which reader claims it, which decoder reads it), and building a
// path object splits the whole path into components each time.
#include <string>

namespace mvox {

// The last component of `path`: what follows the last '/' ("" after a final slash).
std::string file_name_of(const std::string& path);

// The extension of file_name_of(path), dot included and lower-cased (".png"), or "" when the
// name has none: no dot, a name starting with its only dot (".hidden"), "." and "..".
std::string lowercase_extension(const std::string& path);

}  // namespace mvox
