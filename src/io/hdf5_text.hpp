// Strings in HDF5 files that parallel HDF5 can write and xarray can read.
//
// Parallel HDF5 1.10 cannot write variable-length strings, so every string (names, messages,
// text attributes) is fixed-length, null-padded UTF-8. String datasets also carry the attribute
// _Encoding = "utf-8", which makes xarray decode them to str. Sizes are at least 2 bytes: xarray
// takes a 1-byte string type ("S1") for a netCDF char array and h5netcdf leaves S1 attributes
// undecoded, so a one-character name would not come back as a string.
#pragma once
#include <hdf5.h>

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "io/hdf5_handle.hpp"

namespace kanesens::io {

// A fixed-length, null-padded UTF-8 string type of `size` bytes.
Datatype make_string_type(std::size_t size);

// The element size that holds every string of `strings` (at least 2, see above).
std::size_t string_size(const std::vector<std::string>& strings);

// `text` cut to at most `size` bytes; a cut text ends with "..." and never splits a UTF-8
// character.
std::string fit_utf8(std::string_view text, std::size_t size);

// strings.size() × size bytes, each string null-padded (and cut by fit_utf8 if too long).
std::vector<char> pack_strings(const std::vector<std::string>& strings, std::size_t size);

// Reads a 1-D fixed-length string dataset (trailing nulls removed); `path` names it in errors.
std::vector<std::string> read_strings(hid_t dataset, std::string_view path);

// Writes a scalar attribute. Collective under MPI-IO: every rank calls with the same value.
void write_text_attribute(hid_t object, const std::string& name, std::string_view value);
void write_number_attribute(hid_t object, const std::string& name, double value);
// A 1-D float64 attribute (also for 0 values).
void write_numbers_attribute(hid_t object, const std::string& name, std::span<const double> values);

// The text attribute `name` of `object`, or nullopt when it has none. Throws when it is not one
// fixed-length string of at most `max_size` bytes.
std::optional<std::string> read_text_attribute(hid_t object, const std::string& name,
                                               std::size_t max_size = std::size_t{1} << 26);

}  // namespace kanesens::io
