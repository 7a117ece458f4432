// The instruction-set extensions this build's code may use, from the compiler's predefined
// macros at the build's -march. Data only: util/instruction_set.cpp, compiled for the
// architecture's baseline, reads it to check the processor before anything else runs.
namespace kanesens::detail {

// The common extensions a processor can lack (names as __builtin_cpu_supports spells them, each
// also in instruction_set.cpp's known_features): a -march that enables a rarer one can still stop
// at an illegal instruction.
extern const char* const compiled_cpu_features[];
const char* const compiled_cpu_features[] = {
#ifdef __SSE3__
    "sse3",
#endif
#ifdef __SSSE3__
    "ssse3",
#endif
#ifdef __SSE4_1__
    "sse4.1",
#endif
#ifdef __SSE4_2__
    "sse4.2",
#endif
#ifdef __POPCNT__
    "popcnt",
#endif
#ifdef __AVX__
    "avx",
#endif
#ifdef __AVX2__
    "avx2",
#endif
#ifdef __FMA__
    "fma",
#endif
#ifdef __BMI__
    "bmi",
#endif
#ifdef __BMI2__
    "bmi2",
#endif
#ifdef __AVX512F__
    "avx512f",
#endif
#ifdef __AVX512VL__
    "avx512vl",
#endif
#ifdef __AVX512BW__
    "avx512bw",
#endif
#ifdef __AVX512DQ__
    "avx512dq",
#endif
#ifdef __AVX512CD__
    "avx512cd",
#endif
    nullptr};

}  // namespace kanesens::detail
