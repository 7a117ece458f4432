// The tests name the code under test unqualified (or as ks::Name with ks = kanesens::testing):
// every layer's namespace is visible in kanesens::testing.
#pragma once

namespace kanesens::math {}
namespace kanesens::model {}
namespace kanesens::dynamics {}
namespace kanesens::sim {}
namespace kanesens::study {}
namespace kanesens::io {}
namespace kanesens::parallel {}

namespace kanesens::testing {
using namespace kanesens;  // util: InputError, SourceLocation, ...; and the layer namespaces by name
using namespace kanesens::math;
using namespace kanesens::model;
using namespace kanesens::dynamics;
using namespace kanesens::sim;
using namespace kanesens::study;
using namespace kanesens::io;
using namespace kanesens::parallel;
}  // namespace kanesens::testing
