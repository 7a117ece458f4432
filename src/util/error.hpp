// Errors that carry context. InputError is for bad user input (scene/study YAML, --set values):
// it names the file, line, column and key path so the CLI can print one clear line:
//   "configs/x.yaml:12:7: scene.joints[1].parent: unknown body 'link9'; bodies are: rod1, rod2"
// Everything else is a plain std::runtime_error with a message saying which call failed.
#pragma once
#include <stdexcept>
#include <string>

namespace kanesens {

struct SourceLocation {
  std::string file;  // path as the user gave it ("" when not from a file, e.g. --set)
  int line = 0;      // 1-based; 0 = unknown
  int column = 0;    // 1-based; 0 = unknown
};

class InputError : public std::runtime_error {
 public:
  InputError(SourceLocation where, std::string key_path, std::string what)
      : std::runtime_error(format(where, key_path, what)),
        where_(std::move(where)),
        key_path_(std::move(key_path)),
        detail_(std::move(what)) {}
  const SourceLocation& where() const { return where_; }
  const std::string& key_path() const { return key_path_; }
  const std::string& detail() const { return detail_; }

  // A message stays one readable line whatever it quotes (a name of 250 000 characters): each
  // part is cut to this many bytes, between UTF-8 characters.
  static constexpr std::size_t max_part_bytes = 600;
  static std::string shorten(const std::string& text) {
    if (text.size() <= max_part_bytes) return text;
    std::size_t head = max_part_bytes / 2, tail = text.size() - max_part_bytes / 2;
    while (head > 0 && (static_cast<unsigned char>(text[head]) & 0xC0) == 0x80) --head;
    while (tail < text.size() && (static_cast<unsigned char>(text[tail]) & 0xC0) == 0x80) ++tail;
    return text.substr(0, head) + " [... " + std::to_string(tail - head) + " bytes ...] " + text.substr(tail);
  }

  static std::string format(const SourceLocation& w, const std::string& key_in, const std::string& what_in) {
    const std::string key = shorten(key_in), what = shorten(what_in);
    std::string s;
    if (!w.file.empty()) s += w.file;
    if (w.line > 0) {
      s.append(s.empty() ? "line " : ":");
      s.append(std::to_string(w.line));
      if (w.column > 0) {
        s.append(":");
        s.append(std::to_string(w.column));
      }
    }
    if (!s.empty()) s.append(": ");
    if (!key.empty()) {
      s.append(key);
      s.append(": ");
    }
    s.append(what);
    return s;
  }

 private:
  SourceLocation where_;
  std::string key_path_;
  std::string detail_;
};

}  // namespace kanesens
