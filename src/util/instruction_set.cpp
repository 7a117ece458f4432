// What the build was compiled for, and a check at start-up that this processor has it. A binary
// built for the build machine's processor (KANESENS_ARCH=auto: -march=native) and started on an
// older one would otherwise die of an illegal instruction, without a message, at the first AVX2
// or AVX-512 instruction it reaches. This file is compiled for the architecture's baseline
// (src/CMakeLists.txt), so that the check itself runs anywhere; the list of extensions comes
// from util/cpu_features.cpp, compiled like the rest of the build.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "kanesens/version_config.hpp"
#include "util/version.hpp"

namespace kanesens {

namespace detail {
extern const char* const compiled_cpu_features[];  // util/cpu_features.cpp, null-terminated
}

namespace {

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))

// Equality of two C strings, and of a C string with the word [word, end): plain loops, not
// <cstring>'s C++ overloads (inline, and so not necessarily in this file's instruction set).
bool same(const char* a, const char* end, const char* b) {
  while (a != end && *a != '\0' && *b != '\0' && *a == *b) ++a, ++b;
  return (a == end || *a == '\0') && *b == '\0';
}

struct Feature {
  const char* name;
  bool (*supported)();  // __builtin_cpu_supports takes only a literal, hence one function each
};

#define KANESENS_FEATURE(name) {name, []() -> bool { return __builtin_cpu_supports(name) != 0; }},
constexpr Feature known_features[] = {
    KANESENS_FEATURE("sse3") KANESENS_FEATURE("ssse3") KANESENS_FEATURE("sse4.1") KANESENS_FEATURE("sse4.2")
    KANESENS_FEATURE("popcnt") KANESENS_FEATURE("avx") KANESENS_FEATURE("avx2") KANESENS_FEATURE("fma")
    KANESENS_FEATURE("bmi") KANESENS_FEATURE("bmi2") KANESENS_FEATURE("avx512f") KANESENS_FEATURE("avx512vl")
    KANESENS_FEATURE("avx512bw") KANESENS_FEATURE("avx512dq") KANESENS_FEATURE("avx512cd")};
#undef KANESENS_FEATURE

bool supported(const char* name) {
  for (const Feature& f : known_features)
    if (same(f.name, nullptr, name)) return f.supported();
  return true;  // not one this check knows (util/cpu_features.cpp lists only known ones)
}

// Whether `name` is in the space-separated list KANESENS_CPU_FEATURES_MASKED, which makes the
// check treat those extensions as absent (to see and test its message on any machine).
bool masked(const char* name) {
  const char* list = std::getenv("KANESENS_CPU_FEATURES_MASKED");
  if (list == nullptr) return false;
  for (const char* word = list; *word != '\0';) {
    const char* end = word;
    while (*end != '\0' && *end != ' ') ++end;
    if (end != word && same(word, end, name)) return true;
    word = *end == ' ' ? end + 1 : end;
  }
  return false;
}

// Runs before every other static initialiser of the program (priority 101), which this build's
// instructions may already be in.
__attribute__((constructor(101))) void require_compiled_features() {
  __builtin_cpu_init();
  char missing[256];
  std::size_t length = 0;
  missing[0] = '\0';
  for (const char* const* name = detail::compiled_cpu_features; *name != nullptr; ++name) {
    if (supported(*name) && !masked(*name)) continue;
    const char* c = *name;
    if (length + 40 > sizeof missing) break;
    missing[length++] = ' ';
    while (*c != '\0') missing[length++] = *c++;
    missing[length] = '\0';
  }
  if (length == 0) return;
  std::fprintf(stderr,
               "kanesens: error: this processor lacks%s, which this build uses (compiled with -march=%s, "
               "KANESENS_ARCH); rebuild on this machine, or for older processors with "
               "-DKANESENS_ARCH=x86-64-v3, x86-64-v2 or empty (the compiler's baseline)\n",
               missing, KANESENS_ARCH);
  std::_Exit(1);
}

#endif

}  // namespace

// Named on every link line that has kanesens_util (src/CMakeLists.txt), so that this file, and
// with it the check, is in every program built on the engine, not only those that print a version.
extern "C" void kanesens_instruction_set_check() {}

// A build for an instruction set says so (its results may differ at round-off from the
// baseline's), with the extensions the start-up check requires.
std::string instruction_set() {
  const std::string arch = KANESENS_ARCH;
  if (arch.empty()) return "the compiler's baseline";
  std::string text = "-march=" + arch;
  const char* const* name = detail::compiled_cpu_features;
  if (*name == nullptr) return text;
  text.append(" (").append(*name);
  while (*++name != nullptr) text.append(" ").append(*name);
  return text.append(")");
}

}  // namespace kanesens
