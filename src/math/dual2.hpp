// Second-order dual numbers: DualT<Dual>, whose value part carries one outer tangent and whose
// tangent part the inner one. Evaluating the model on Dual2 with the inner tangent along a state
// direction and the outer along a parameter gives ∂²f/∂x∂p exactly — the parameter derivative of
// a column of the linearized A (sim/linearize.hpp), which eigenvalue sensitivities need.
// Only the layers that evaluate on it include this header (the instantiations cost compile time).
#pragma once
#include "math/dual.hpp"

namespace kanesens::math {
using Dual2 = DualT<Dual>;
}  // namespace kanesens::math

namespace Eigen {
template <>
struct NumTraits<kanesens::math::Dual2> : kanesens::math::DualNumTraits<kanesens::math::Dual2, 4, 4, 9> {};
}  // namespace Eigen
