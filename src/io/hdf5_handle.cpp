#include "io/hdf5_handle.hpp"

#include <stdexcept>

namespace kanesens::io {
namespace {

// H5Ewalk2 callback: keeps the description of the innermost (first, walking upward) error,
// which says what actually went wrong ("unable to open file: ... errno = 17, File exists").
herr_t keep_innermost(unsigned n, const H5E_error2_t* err, void* client) {
  auto& message = *static_cast<std::string*>(client);
  if (n == 0 && err != nullptr && err->desc != nullptr) message = err->desc;
  return 0;
}

std::string take_error_message() {
  std::string message;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, keep_innermost, &message);
  H5Eclear2(H5E_DEFAULT);
  return message;
}

}  // namespace

std::string hdf5_version() {
  std::string v = std::to_string(H5_VERS_MAJOR) + "." + std::to_string(H5_VERS_MINOR) + "." +
                  std::to_string(H5_VERS_RELEASE);
#ifdef H5_HAVE_PARALLEL
  v += " (parallel)";
#endif
  return v;
}

void silence_hdf5_errors() {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

void check(herr_t status, std::string_view call) {
  if (status >= 0) return;
  std::string what = "HDF5 call " + std::string(call) + " failed";
  const std::string detail = take_error_message();
  if (!detail.empty()) what += ": " + detail;
  throw std::runtime_error(what);
}

hid_t check_id(hid_t id, std::string_view call) {
  check(id < 0 ? -1 : 0, call);
  return id;
}

}  // namespace kanesens::io
