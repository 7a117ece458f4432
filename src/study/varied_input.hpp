// One input of the study that the design varies: a scene parameter ("m2") or an initial
// condition ("shoulder.q0"), and its distribution.
#pragma once
#include <string>

#include "study/distribution.hpp"

namespace kanesens::study {

struct VariedInput {
  std::string name;
  Distribution dist;
};

}  // namespace kanesens::study
