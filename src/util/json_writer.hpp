// A small streaming JSON writer (objects, arrays, numbers, strings) for CLI output.
// Doubles are written with 17 significant digits so they round-trip; NaN/Inf become null.
#pragma once
#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

#include "util/input_text.hpp"

namespace kanesens {

class JsonWriter {
 public:
  explicit JsonWriter(std::ostream& out) : out_(out) {}

  JsonWriter& begin_object() { value_prefix(); out_ << '{'; first_.push_back(true); return *this; }
  JsonWriter& end_object() { first_.pop_back(); out_ << '}'; return *this; }
  JsonWriter& begin_array() { value_prefix(); out_ << '['; first_.push_back(true); return *this; }
  JsonWriter& end_array() { first_.pop_back(); out_ << ']'; return *this; }
  JsonWriter& key(const std::string& k) {
    if (!first_.back()) out_ << ',';
    first_.back() = false;
    out_ << '\n' << std::string(2 * first_.size(), ' ');
    write_string(k);
    out_ << ": ";
    after_key_ = true;
    return *this;
  }
  JsonWriter& value(double v) {
    value_prefix();
    if (!std::isfinite(v)) {
      out_ << "null";
    } else {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.17g", v);
      out_ << buf;
    }
    return *this;
  }
  JsonWriter& value(long long v) { value_prefix(); out_ << v; return *this; }
  JsonWriter& value(int v) { return value(static_cast<long long>(v)); }
  JsonWriter& value(bool v) { value_prefix(); out_ << (v ? "true" : "false"); return *this; }
  JsonWriter& value(const std::string& s) { value_prefix(); write_string(s); return *this; }
  JsonWriter& value(const char* s) { return value(std::string(s)); }
  template <class Range>
  JsonWriter& array(const Range& r) {
    begin_array();
    for (const auto& x : r) value(x);
    return end_array();
  }
  JsonWriter& array(const double* p, std::size_t n) {
    begin_array();
    for (std::size_t i = 0; i < n; ++i) value(p[i]);
    return end_array();
  }

 private:
  void value_prefix() {
    if (after_key_) {
      after_key_ = false;
      return;
    }
    if (!first_.empty()) {
      if (!first_.back()) out_ << ", ";
      first_.back() = false;
    }
  }
  void write_string(const std::string& raw) {
    // JSON is UTF-8: a name is valid UTF-8 by the time it gets here (input files are checked),
    // but a message may quote a command-line argument.
    const std::string s = first_invalid_utf8(raw) == raw.size() ? raw : to_valid_utf8(raw);
    out_ << '"';
    for (char c : s) {
      switch (c) {
        case '"': out_ << "\\\""; break;
        case '\\': out_ << "\\\\"; break;
        case '\n': out_ << "\\n"; break;
        case '\t': out_ << "\\t"; break;
        default:
          if (static_cast<unsigned char>(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            out_ << buf;
          } else {
            out_ << c;
          }
      }
    }
    out_ << '"';
  }
  std::ostream& out_;
  std::vector<bool> first_;
  bool after_key_ = false;
};

}  // namespace kanesens
