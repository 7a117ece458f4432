#include <gtest/gtest.h>

#include "io/hdf5_handle.hpp"
#include "io/hdf5_text.hpp"

namespace kanesens::io {
namespace {

TEST(FitUtf8, KeepsShortTextAndCutsLongTextWithDots) {
  EXPECT_EQ(fit_utf8("short", 10), "short");
  EXPECT_EQ(fit_utf8("0123456789abc", 10), "0123456...");
}

TEST(FitUtf8, NeverSplitsACharacter) {
  // "αβγδ" is 8 bytes (2 each); 8 bytes of room leave 5 for text: "αβ" (4) + "...".
  EXPECT_EQ(fit_utf8("αβγδx", 8), "αβ...");
}

TEST(PackStrings, NullPadsEachString) {
  const auto packed = pack_strings({"ab", "c"}, 3);
  EXPECT_EQ(std::string(packed.data(), packed.size()), std::string("ab\0c\0\0", 6));
  EXPECT_EQ(string_size({"a"}), 2u);  // never 1 byte: xarray would take "S1" for a char array
  EXPECT_EQ(string_size({"a", "abcd"}), 4u);
}

TEST(Check, NamesTheCallAndHdf5sReason) {
  silence_hdf5_errors();
  try {
    File file(H5Fopen("/nonexistent/dir/x.h5", H5F_ACC_RDONLY, H5P_DEFAULT),
              "H5Fopen(/nonexistent/dir/x.h5)");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("HDF5 call H5Fopen(/nonexistent/dir/x.h5) failed: "), std::string::npos)
        << what;
    EXPECT_NE(what.find("No such file"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace kanesens::io
