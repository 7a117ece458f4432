#include "io/hdf5_text.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace kanesens::io {

Datatype make_string_type(std::size_t size) {
  Datatype type(H5Tcopy(H5T_C_S1), "H5Tcopy(H5T_C_S1)");
  check(H5Tset_size(type.get(), std::max<std::size_t>(size, 2)), "H5Tset_size");
  check(H5Tset_strpad(type.get(), H5T_STR_NULLPAD), "H5Tset_strpad");
  check(H5Tset_cset(type.get(), H5T_CSET_UTF8), "H5Tset_cset");
  return type;
}

std::size_t string_size(const std::vector<std::string>& strings) {
  std::size_t size = 2;
  for (const auto& s : strings) size = std::max(size, s.size());
  return size;
}

std::string fit_utf8(std::string_view text, std::size_t size) {
  if (text.size() <= size) return std::string(text);
  if (size < 3) return std::string(size, '.');
  std::size_t keep = size - 3;
  // Back off over UTF-8 continuation bytes (10xxxxxx) so the cut falls between characters.
  while (keep > 0 && (static_cast<unsigned char>(text[keep]) & 0xC0) == 0x80) --keep;
  return std::string(text.substr(0, keep)) + "...";
}

std::vector<char> pack_strings(const std::vector<std::string>& strings, std::size_t size) {
  std::vector<char> buffer(strings.size() * size, '\0');
  for (std::size_t i = 0; i < strings.size(); ++i) {
    const std::string s = fit_utf8(strings[i], size);
    std::memcpy(buffer.data() + i * size, s.data(), s.size());
  }
  return buffer;
}

std::vector<std::string> read_strings(hid_t dataset, std::string_view path) {
  std::string where = "(";  // built stepwise: `"(" + std::string(path)` trips GCC 12 -Wrestrict
  where.append(path).append(")");
  Datatype type(H5Dget_type(dataset), "H5Dget_type" + where);
  if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) > 0) {
    throw std::runtime_error("HDF5 dataset " + std::string(path) +
                             " is not a fixed-length string dataset");
  }
  const std::size_t size = H5Tget_size(type.get());
  Dataspace space(H5Dget_space(dataset), "H5Dget_space" + where);
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  check(n < 0 ? -1 : 0, "H5Sget_simple_extent_npoints" + where);
  std::vector<char> buffer(static_cast<std::size_t>(n) * size);
  if (n > 0) {
    check(H5Dread(dataset, type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()),
          "H5Dread" + where);
  }
  std::vector<std::string> strings;
  for (hssize_t i = 0; i < n; ++i) {
    const char* s = buffer.data() + static_cast<std::size_t>(i) * size;
    strings.emplace_back(s, strnlen(s, size));
  }
  return strings;
}

void write_text_attribute(hid_t object, const std::string& name, std::string_view value) {
  const std::string where = "(@" + name + ")";
  const Datatype type = make_string_type(value.size());
  Dataspace space(H5Screate(H5S_SCALAR), "H5Screate" + where);
  Attribute attr(
      H5Acreate2(object, name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT),
      "H5Acreate2" + where);
  std::vector<char> buffer(H5Tget_size(type.get()), '\0');
  std::memcpy(buffer.data(), value.data(), value.size());
  check(H5Awrite(attr.get(), type.get(), buffer.data()), "H5Awrite" + where);
}

void write_number_attribute(hid_t object, const std::string& name, double value) {
  const std::string where = "(@" + name + ")";
  Dataspace space(H5Screate(H5S_SCALAR), "H5Screate" + where);
  Attribute attr(
      H5Acreate2(object, name.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT),
      "H5Acreate2" + where);
  check(H5Awrite(attr.get(), H5T_NATIVE_DOUBLE, &value), "H5Awrite" + where);
}

void write_numbers_attribute(hid_t object, const std::string& name,
                             std::span<const double> values) {
  const std::string where = "(@" + name + ")";
  const hsize_t n = values.size();
  Dataspace space(H5Screate_simple(1, &n, nullptr), "H5Screate_simple" + where);
  Attribute attr(
      H5Acreate2(object, name.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT),
      "H5Acreate2" + where);
  check(H5Awrite(attr.get(), H5T_NATIVE_DOUBLE, values.data()), "H5Awrite" + where);
}

std::optional<std::string> read_text_attribute(hid_t object, const std::string& name, std::size_t max_size) {
  const std::string where = "(@" + name + ")";
  const htri_t exists = H5Aexists(object, name.c_str());
  check(exists < 0 ? -1 : 0, "H5Aexists" + where);
  if (exists == 0) return std::nullopt;
  Attribute attr(H5Aopen(object, name.c_str(), H5P_DEFAULT), "H5Aopen" + where);
  Datatype type(H5Aget_type(attr.get()), "H5Aget_type" + where);
  if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) > 0) {
    throw std::runtime_error("HDF5 attribute " + name + " is not a fixed-length string");
  }
  // The buffer holds exactly one string: an attribute of several elements (a hostile file) would
  // be read past its end.
  Dataspace space(H5Aget_space(attr.get()), "H5Aget_space" + where);
  if (H5Sget_simple_extent_npoints(space.get()) != 1) {
    throw std::runtime_error("HDF5 attribute " + name + " is not a single string");
  }
  if (H5Tget_size(type.get()) > max_size) {
    throw std::runtime_error("HDF5 attribute " + name + " is longer than " + std::to_string(max_size) + " bytes");
  }
  std::vector<char> buffer(H5Tget_size(type.get()), '\0');
  check(H5Aread(attr.get(), type.get(), buffer.data()), "H5Aread" + where);
  return std::string(buffer.data(), strnlen(buffer.data(), buffer.size()));
}

}  // namespace kanesens::io
