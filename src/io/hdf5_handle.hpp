// RAII ownership of HDF5 identifiers (hid_t) and the check() helper that turns a failed HDF5
// call into an exception naming the call, the object path and HDF5's own innermost message.
//
// HDF5's automatic error-stack printing is switched off (silence_hdf5_errors()): a failure
// reaches the user once, as the exception's one-line message, instead of as a stack dump on
// every rank.
#pragma once
#include <hdf5.h>

#include <string>
#include <string_view>
#include <utility>

namespace kanesens::io {

// "1.10.8 (parallel)": the HDF5 this build links.
std::string hdf5_version();

// Turns off HDF5's automatic printing of its error stack for this process (idempotent).
void silence_hdf5_errors();

// Throws std::runtime_error("HDF5 call H5Dwrite(/states) failed: <HDF5's message>") when
// status < 0, `call` naming the function and the object, e.g. "H5Dwrite(/states)".
void check(herr_t status, std::string_view call);

// As check(), for calls returning an identifier (negative on failure); returns `id`.
hid_t check_id(hid_t id, std::string_view call);

// Owns one HDF5 identifier and releases it with `Close` (H5Fclose, H5Dclose, ...). Move-only.
template <herr_t (*Close)(hid_t)>
class Handle {
 public:
  Handle() = default;
  // Takes ownership of the result of `call`, throwing (see check_id) when it is negative.
  Handle(hid_t id, std::string_view call) : id_(check_id(id, call)) {}
  ~Handle() { reset(); }
  Handle(Handle&& other) noexcept : id_(std::exchange(other.id_, H5I_INVALID_HID)) {}
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      reset();
      id_ = std::exchange(other.id_, H5I_INVALID_HID);
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;

  hid_t get() const { return id_; }
  explicit operator bool() const { return id_ >= 0; }

  // Releases the identifier, ignoring failure (for destructors and error paths).
  void reset() noexcept {
    if (id_ >= 0) Close(id_);
    id_ = H5I_INVALID_HID;
  }
  // Forgets the identifier without closing it. For error paths under MPI where a collective
  // close could wait forever for ranks that are not in step (the process is about to abort).
  void abandon() noexcept { id_ = H5I_INVALID_HID; }
  // Releases the identifier and throws if HDF5 reports a failure (e.g. a collective H5Fclose).
  void close(std::string_view call) {
    if (id_ >= 0) check(Close(std::exchange(id_, H5I_INVALID_HID)), call);
  }

 private:
  hid_t id_ = H5I_INVALID_HID;
};

using File = Handle<H5Fclose>;
using Group = Handle<H5Gclose>;
using Dataset = Handle<H5Dclose>;
using Dataspace = Handle<H5Sclose>;
using Datatype = Handle<H5Tclose>;
using PropertyList = Handle<H5Pclose>;
using Attribute = Handle<H5Aclose>;

}  // namespace kanesens::io
