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

  static std::string format(const SourceLocation& w, const std::string& key, const std::string& what) {
    std::string s;
    if (!w.file.empty()) s += w.file;
    // Appends piece by piece: `"literal" + std::string` here trips GCC 12's -Wrestrict false
    // positive (GCC bug 105651) once inlined at -O2/-O3.
    if (w.line > 0) {
      s += s.empty() ? "line " : ":";
      s += std::to_string(w.line);
      if (w.column > 0) {
        s += ':';
        s += std::to_string(w.column);
      }
    }
    if (!s.empty()) s += ": ";
    if (!key.empty()) {
      s += key;
      s += ": ";
    }
    s += what;
    return s;
  }

 private:
  SourceLocation where_;
  std::string key_path_;
  std::string detail_;
};

}  // namespace kanesens
