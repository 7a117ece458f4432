// Run ordering of a Saltelli design (Saltelli 2002; Saltelli et al. 2010, "Variance based
// sensitivity analysis of model output", Comput. Phys. Commun. 181). Base point j (0 ≤ j < N)
// is a 2P-dimensional point [A_j | B_j]; the runs of base point j form one block of P + 2
// consecutive runs:
//   run j·(P+2) + 0       A_j
//   run j·(P+2) + 1       B_j
//   run j·(P+2) + 2 + k   AB_j^(k) = A_j with column k (0-based) taken from B_j
// so the estimators of first-order and total indices (Saltelli 2010, Jansen 1999) need only the
// rows of one block at a time. With the unrandomized Sobol' base, base point 0 is Sobol' point 1
// = (½, …, ½), so A_0 = B_0 and block 0 adds nothing to the differences f(A) − f(AB); it biases
// nothing but is one wasted block — `randomize: true` avoids it.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

namespace kanesens::study {

enum class SaltelliBlock { A, B, AB };

struct SaltelliIndex {
  std::int64_t base = 0;  // j, the base point
  SaltelliBlock block = SaltelliBlock::A;
  std::size_t input = 0;  // k for AB^(k) (0-based input index); 0 for A and B
};

inline SaltelliIndex saltelli_index(std::int64_t run, std::size_t dimension) {
  const auto width = static_cast<std::int64_t>(dimension) + 2;
  const std::int64_t slot = run % width;
  SaltelliIndex s;
  s.base = run / width;
  s.block = slot == 0 ? SaltelliBlock::A : slot == 1 ? SaltelliBlock::B : SaltelliBlock::AB;
  s.input = slot >= 2 ? static_cast<std::size_t>(slot - 2) : 0;
  return s;
}

// "A", "B", "AB0", "AB1", ... (input indices 0-based, like the HDF5 parameter dimension).
inline std::string saltelli_label(const SaltelliIndex& s) {
  switch (s.block) {
    case SaltelliBlock::A:
      return "A";
    case SaltelliBlock::B:
      return "B";
    case SaltelliBlock::AB:
      break;
  }
  return "AB" + std::to_string(s.input);
}

}  // namespace kanesens::study
