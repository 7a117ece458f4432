// The serial N_Vector's operations, compiled with the project: CVODES updates the state, its
// history and every sensitivity through them, a few times per step each.
//
// Why not SUNDIALS's own: the libsundials of Debian 12 (6.4) is built without optimisation, so
// each of its vector operations spills every index and pointer to the stack, at about twenty
// instructions per entry; on a BDF solve with sensitivities they were half of all instructions
// (docs/benchmarks.md, "CVODES's vector operations"). These are the same operations with the same
// special cases (a = ±1, a = ±b, in-place forms) and the same order of every sum, so the results
// are SUNDIALS's to the bit (tests/unit/test_serial_vector_ops.cpp compares every operation with
// the library's). Fused and vector-array operations are included: CVODES updates the Ns
// sensitivity vectors with one call per operation instead of one per vector.
#pragma once
#include <sundials/sundials_nvector.h>

namespace kanesens::sim {

// Points every arithmetic operation of serial vector v at the compiled ones (and enables the
// fused and vector-array operations). Clones made afterwards inherit them, and their data start
// on a 64-byte boundary. Throws std::invalid_argument unless v is a serial vector.
void use_compiled_serial_ops(N_Vector v);

// The largest block size use_block_error_norm takes.
inline constexpr int kMaxErrorNormBlock = 64;

// For a state stacked with its sensitivities in one serial vector v, [y; s_0; …] (blocks of
// `block` entries): makes v's WRMS norm (and its later clones') the largest of its blocks' WRMS
// norms (every_block), the norm CVODES's sensitivity module tests with sensitivity error control,
// or the first block's alone, the one it tests without. False, with nothing changed, unless v is
// serial, 1 ≤ block ≤ kMaxErrorNormBlock and block divides v's length.
bool use_block_error_norm(N_Vector v, int block, bool every_block);

}  // namespace kanesens::sim
