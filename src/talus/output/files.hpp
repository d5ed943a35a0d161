// Writing files so that no reader ever sees half of one: write a temporary beside the target,
// flush it to disk, then rename it over the target.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

namespace talus {

class OutputError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

// Replaces `path` with `content` atomically. Throws OutputError naming the file and the reason.
void write_file_atomic(const std::string& path, std::string_view content);

} // namespace talus
