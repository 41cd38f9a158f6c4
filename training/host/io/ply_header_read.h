// Private: header parsing on an open file, leaving it positioned at the first data byte, so the
// data reader does not reopen the file.
#pragma once
#include <cstdio>
#include <filesystem>

#include "s4d/io/ply_header.h"

namespace s4d::io::detail {

// `path` only names the file in errors.
PlyHeader read_ply_header(std::FILE* f, const std::filesystem::path& path);

}  // namespace s4d::io::detail
