#include "util/input_text.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include "util/error.hpp"

namespace kanesens {

std::string read_input_file(const std::string& path, std::size_t limit) {
  struct stat info {};
  if (::stat(path.c_str(), &info) == 0 && S_ISDIR(info.st_mode))
    throw InputError({path, 0, 0}, "", "is a directory, not a YAML file");
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> in(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!in) throw InputError({path, 0, 0}, "", "cannot open file");
  std::string text;
  char buffer[1 << 16];
  // Reads at most limit + 1 bytes, whatever the file claims to be (a device, a pipe, /proc).
  while (text.size() <= limit) {
    const std::size_t want = std::min(sizeof buffer, limit + 1 - text.size());
    const std::size_t got = std::fread(buffer, 1, want, in.get());
    text.append(buffer, got);
    if (got < want) {
      if (std::ferror(in.get()))
        throw InputError({path, 0, 0}, "", std::string("cannot read file: ") + std::strerror(errno));
      break;
    }
  }
  if (text.size() > limit)
    throw InputError({path, 0, 0}, "",
                     "file is larger than " + std::to_string(limit >> 20) + " MiB; a scene or study file is far smaller");
  return text;
}

std::size_t first_invalid_utf8(std::string_view s) {
  const auto* p = reinterpret_cast<const unsigned char*>(s.data());
  const std::size_t n = s.size();
  std::size_t i = 0;
  while (i < n) {
    const unsigned c = p[i];
    if (c < 0x80) {
      ++i;
      continue;
    }
    std::size_t len = 0;
    unsigned lo = 0x80, hi = 0xBF;  // allowed range of the second byte
    if (c >= 0xC2 && c <= 0xDF) {
      len = 2;
    } else if (c >= 0xE0 && c <= 0xEF) {
      len = 3;
      if (c == 0xE0) lo = 0xA0;  // overlong
      if (c == 0xED) hi = 0x9F;  // surrogates
    } else if (c >= 0xF0 && c <= 0xF4) {
      len = 4;
      if (c == 0xF0) lo = 0x90;  // overlong
      if (c == 0xF4) hi = 0x8F;  // above U+10FFFF
    } else {
      return i;
    }
    if (i + len > n || p[i + 1] < lo || p[i + 1] > hi) return i;
    for (std::size_t k = 2; k < len; ++k)
      if (p[i + k] < 0x80 || p[i + k] > 0xBF) return i;
    i += len;
  }
  return n;
}

std::string to_valid_utf8(std::string_view text) {
  std::string out;
  for (;;) {
    const std::size_t bad = first_invalid_utf8(text);
    out.append(text.substr(0, bad));
    if (bad == text.size()) return out;
    out.append("\xEF\xBF\xBD");
    text.remove_prefix(bad + 1);
  }
}

void check_input_text(std::string_view text, const std::string& file) {
  const std::size_t bad_utf8 = first_invalid_utf8(text);
  std::size_t bad = bad_utf8;
  for (std::size_t i = 0; i < bad_utf8; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if ((c < 0x20 && c != '\t' && c != '\n' && c != '\r') || c == 0x7F) {
      bad = i;
      break;
    }
  }
  if (bad == text.size()) return;
  int line = 1, column = 1;
  for (std::size_t i = 0; i < bad; ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else if ((static_cast<unsigned char>(text[i]) & 0xC0) != 0x80) {  // count characters, not bytes
      ++column;
    }
  }
  char byte[8];
  std::snprintf(byte, sizeof byte, "0x%02X", static_cast<unsigned char>(text[bad]));
  throw InputError({file, line, column}, "",
                   bad == bad_utf8 ? std::string("invalid UTF-8 (byte ") + byte + "); the file must be UTF-8 text"
                                   : std::string("control character ") + byte + " is not allowed in YAML text");
}

}  // namespace kanesens
