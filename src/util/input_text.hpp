// Input files are read through here: bounded in size (a YAML file of 16 MiB is far larger than
// any scene or study; /dev/zero or a wrong path to a data file must not read until memory runs
// out) and checked to be text (UTF-8 without control characters), so names that end up in JSON,
// HDF5 strings and messages are always valid UTF-8.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>

namespace kanesens {

// Largest input file accepted, bytes.
inline constexpr std::size_t kMaxInputFileBytes = std::size_t{16} << 20;

// The whole of `path`. InputError naming the file when it cannot be opened, is a directory, or
// holds more than `limit` bytes (only limit + 1 bytes are ever read).
std::string read_input_file(const std::string& path, std::size_t limit = kMaxInputFileBytes);

// Throws InputError at file:line:column of the first byte of `text` that is not valid UTF-8
// (overlong forms, surrogates and code points above U+10FFFF included) or that is a control
// character other than tab, line feed and carriage return (YAML allows no others).
void check_input_text(std::string_view text, const std::string& file);

// The offset of the first invalid UTF-8 sequence of `text`, or text.size() when it is valid.
std::size_t first_invalid_utf8(std::string_view text);

// `text` with every byte that does not start a valid UTF-8 sequence replaced by U+FFFD (for
// output that must be UTF-8 whatever it quotes, e.g. JSON).
std::string to_valid_utf8(std::string_view text);

}  // namespace kanesens
