#include "libbead/io/hdf5_file.h"

#include <algorithm>
#include <sstream>

#include "libbead/core/error.h"

namespace bead::h5 {
namespace {

bool StandardFloat(hid_t type) {
  for (hid_t ieee : {H5T_IEEE_F32LE, H5T_IEEE_F32BE, H5T_IEEE_F64LE, H5T_IEEE_F64BE})
    if (H5Tequal(type, ieee) > 0) return true;
  return false;
}

bool StandardInteger(hid_t type) {
  const std::size_t size = H5Tget_size(type);
  return (size == 1 || size == 2 || size == 4 || size == 8) && H5Tget_precision(type) == 8 * size &&
         H5Tget_offset(type) == 0;
}

// HDF5 prints its error stack to stderr by default; we report ourselves.
void SilenceHdf5() {
  static const bool silenced = [] {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
  }();
  (void)silenced;
}

std::string Shape(const std::vector<hsize_t>& dims) {
  std::ostringstream out;
  out << "[";
  for (std::size_t i = 0; i < dims.size(); ++i) out << (i ? ", " : "") << dims[i];
  out << "]";
  return out.str();
}

std::string RanksText(std::initializer_list<int> ranks) {
  std::ostringstream out;
  bool first = true;
  for (int r : ranks) {
    out << (first ? "" : " or ") << r;
    first = false;
  }
  return out.str();
}

}  // namespace

void Handle::reset() {
  if (id_ >= 0 && close_) close_(id_);
  id_ = H5I_INVALID_HID;
}

File File::OpenReadWrite(const std::string& path) {
  File f = OpenRead(path);  // the same checks and messages
  f.handle_.reset();        // one open of a file at a time (HDF5 refuses a second with other rights)
  f.handle_ = Handle(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
  if (!f.handle_.valid()) throw Error(Located(path, "", "cannot open for writing"));
  return f;
}

File File::OpenRead(const std::string& path) {
  SilenceHdf5();
  File f;
  f.name_ = path;
  if (H5Fis_hdf5(path.c_str()) <= 0) {
    FILE* probe = std::fopen(path.c_str(), "rb");
    if (!probe) throw Error(Located(path, "", "cannot open: no such file or not readable"));
    std::fclose(probe);
    throw Error(Located(path, "", "not an HDF5 file"));
  }
  f.handle_ = Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!f.handle_.valid()) throw Error(Located(path, "", "cannot open as HDF5 (damaged or truncated?)"));
  return f;
}

File File::Create(const std::string& path, const std::string& display_name) {
  SilenceHdf5();
  File f;
  f.name_ = display_name;
  f.handle_ = Handle(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
  if (!f.handle_.valid()) throw Error(Located(display_name, "", "cannot create HDF5 file"));
  return f;
}

bool File::Exists(const std::string& object) const {
  // Check each path component so that a missing parent is not an error.
  std::size_t pos = 0;
  while (true) {
    pos = object.find('/', pos + 1);
    const std::string part = object.substr(0, pos);
    if (!part.empty() && part != "/" && H5Lexists(id(), part.c_str(), H5P_DEFAULT) <= 0) return false;
    if (pos == std::string::npos) return true;
  }
}

// A dataset's declared shape against what the file stores for it, before
// anything is allocated: a damaged header can declare 10^18 values. Without
// filters the values take their full size on disk; with them (deflate) at
// most about 1032 times less (zlib's bound on the deflate ratio), so more
// than 1100 times the stored bytes (+1 MiB) is refused.
void File::CheckStoredSize(hid_t ds, hid_t type, const std::vector<hsize_t>& dims, const std::string& dataset) const {
  const double limit = 4e9;  // values: far beyond any run (16 GB as float32)
  double total = 1;
  for (hsize_t d : dims) total *= static_cast<double>(d);
  if (total > limit)
    throw Error(Located(name_, dataset, "declares " + Shape(dims) + " values: damaged, or beyond what libbead reads"));
  const double bytes = total * static_cast<double>(H5Tget_size(type));
  const double stored = static_cast<double>(H5Dget_storage_size(ds));
  Handle dcpl(H5Dget_create_plist(ds), H5Pclose);
  const int filters = dcpl.valid() ? H5Pget_nfilters(dcpl.get()) : 0;
  const double room = filters > 0 ? 1100.0 * stored + 1048576.0 : stored;
  if (total > 0 && bytes > room)
    throw Error(Located(name_, dataset,
                        "declares " + Shape(dims) + " values (" + std::to_string(static_cast<long long>(bytes)) +
                            " bytes) but the file stores " + std::to_string(static_cast<long long>(stored)) +
                            " bytes for it: truncated or damaged"));
}

Handle File::OpenDataset(const std::string& dataset, std::initializer_list<int> ranks, Kind kind,
                         std::vector<hsize_t>& dims) const {
  if (!Exists(dataset)) throw Error(Located(name_, dataset, "missing dataset"));
  Handle ds(H5Dopen2(id(), dataset.c_str(), H5P_DEFAULT), H5Dclose);
  if (!ds.valid()) throw Error(Located(name_, dataset, "is not a dataset"));
  Handle type(H5Dget_type(ds.get()), H5Tclose);
  const H5T_class_t cls = H5Tget_class(type.get());
  if (kind == Kind::kFloat && cls != H5T_FLOAT)
    throw Error(Located(name_, dataset, "wrong type: expected a floating-point number"));
  if (kind == Kind::kInteger && cls != H5T_INTEGER)
    throw Error(Located(name_, dataset, "wrong type: expected integer encoder counts"));
  // Only the types the format names (docs/data-formats.md): libhdf5
  // converts any other float or integer layout in software, slowly and
  // with buffers sized from the damaged header.
  if (cls == H5T_FLOAT && !StandardFloat(type.get()))
    throw Error(Located(name_, dataset,
                        "wrong type: a floating-point layout other than IEEE float32 or float64 (" +
                            std::to_string(H5Tget_precision(type.get())) + " bits in " +
                            std::to_string(H5Tget_size(type.get())) + " bytes)"));
  if (cls == H5T_INTEGER && !StandardInteger(type.get()))
    throw Error(Located(name_, dataset,
                        "wrong type: an integer layout other than 8, 16, 32 or 64 bits (" +
                            std::to_string(H5Tget_precision(type.get())) + " bits in " +
                            std::to_string(H5Tget_size(type.get())) + " bytes)"));
  Handle space(H5Dget_space(ds.get()), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (std::find(ranks.begin(), ranks.end(), rank) == ranks.end())
    throw Error(Located(name_, dataset,
                        "wrong shape: has " + std::to_string(rank) + " dimensions, expected " + RanksText(ranks)));
  dims.resize(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  CheckStoredSize(ds.get(), type.get(), dims, dataset);
  return ds;
}

template <typename T>
Array<T> File::Read(const std::string& dataset, std::initializer_list<int> ranks, Kind kind, hid_t mem_type) const {
  Array<T> out;
  const Handle ds = OpenDataset(dataset, ranks, kind, out.dims);
  hsize_t total = 1;
  for (hsize_t d : out.dims) total *= d;
  out.data.resize(total);
  if (total > 0 && H5Dread(ds.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data.data()) < 0)
    throw Error(Located(name_, dataset, "cannot read values " + Shape(out.dims) + " (damaged, or out of range?)"));
  return out;
}

Array<double> File::ReadDouble(const std::string& dataset, std::initializer_list<int> ranks) const {
  return Read<double>(dataset, ranks, Kind::kFloat, H5T_NATIVE_DOUBLE);
}
Array<float> File::ReadFloat(const std::string& dataset, std::initializer_list<int> ranks) const {
  return Read<float>(dataset, ranks, Kind::kFloat, H5T_NATIVE_FLOAT);
}
Array<int64_t> File::ReadInt64(const std::string& dataset, std::initializer_list<int> ranks) const {
  return Read<int64_t>(dataset, ranks, Kind::kInteger, H5T_NATIVE_INT64);
}

void File::CreateGroup(const std::string& group) {
  // One level at a time, without modification times, so that the same
  // content gives the same bytes (simulated samples regenerate bit for bit).
  std::size_t pos = 0;
  while (pos != std::string::npos) {
    pos = group.find('/', pos + 1);
    const std::string part = group.substr(0, pos);
    if (part.empty() || part == "/" || Exists(part)) continue;
    Handle gcpl(H5Pcreate(H5P_GROUP_CREATE), H5Pclose);
    H5Pset_obj_track_times(gcpl.get(), 0);
    Handle g(H5Gcreate2(id(), part.c_str(), H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), H5Gclose);
    if (!g.valid()) throw Error(Located(name_, part, "cannot create group"));
  }
}

template <typename T>
void File::WriteImpl(const std::string& dataset, const std::vector<T>& data, const std::vector<hsize_t>& dims,
                     hid_t file_type, hid_t mem_type) {
  hsize_t total = 1;
  for (hsize_t d : dims) total *= d;
  if (total != data.size()) throw Error(Located(name_, dataset, "internal: data size does not match shape"));
  Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  H5Pset_obj_track_times(dcpl.get(), 0);
  if (const auto slash = dataset.rfind('/'); slash != std::string::npos && slash > 0)
    CreateGroup(dataset.substr(0, slash));
  if (total >= 4096 && !dims.empty() && dims[0] > 0) {
    // Chunks of whole rows, about 256 KiB, compressed.
    std::vector<hsize_t> chunk = dims;
    const hsize_t row = total / dims[0];
    chunk[0] = std::clamp<hsize_t>((256 * 1024 / sizeof(T)) / std::max<hsize_t>(row, 1), 1, dims[0]);
    H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data());
    H5Pset_shuffle(dcpl.get());
    H5Pset_deflate(dcpl.get(), 4);
  }
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  H5Pset_create_intermediate_group(lcpl.get(), 1);
  Handle ds(H5Dcreate2(id(), dataset.c_str(), file_type, space.get(), lcpl.get(), dcpl.get(), H5P_DEFAULT), H5Dclose);
  if (!ds.valid()) throw Error(Located(name_, dataset, "cannot create dataset"));
  if (total > 0 && H5Dwrite(ds.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) < 0)
    throw Error(Located(name_, dataset, "cannot write dataset (disk full?)"));
}

void File::Write(const std::string& dataset, const std::vector<double>& data, const std::vector<hsize_t>& dims) {
  WriteImpl(dataset, data, dims, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE);
}
void File::Write(const std::string& dataset, const std::vector<float>& data, const std::vector<hsize_t>& dims) {
  WriteImpl(dataset, data, dims, H5T_IEEE_F32LE, H5T_NATIVE_FLOAT);
}
void File::Write(const std::string& dataset, const std::vector<int64_t>& data, const std::vector<hsize_t>& dims) {
  WriteImpl(dataset, data, dims, H5T_STD_I64LE, H5T_NATIVE_INT64);
}

std::map<std::string, std::string> File::ReadStringAttributes(const std::string& object) const {
  std::map<std::string, std::string> out;
  Handle obj(H5Oopen(id(), object.c_str(), H5P_DEFAULT), H5Oclose);
  if (!obj.valid()) return out;
  H5O_info_t info;
  if (H5Oget_info(obj.get(), &info) < 0) return out;
  for (hsize_t i = 0; i < info.num_attrs; ++i) {
    Handle attr(H5Aopen_by_idx(obj.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
    if (!attr.valid()) continue;
    char name[256] = {0};
    H5Aget_name(attr.get(), sizeof(name) - 1, name);
    Handle type(H5Aget_type(attr.get()), H5Tclose);
    if (H5Tget_class(type.get()) != H5T_STRING) continue;
    Handle space(H5Aget_space(attr.get()), H5Sclose);
    if (H5Sget_simple_extent_npoints(space.get()) != 1) continue;
    if (H5Tis_variable_str(type.get()) > 0) {
      char* value = nullptr;
      Handle mem(H5Tcopy(H5T_C_S1), H5Tclose);
      H5Tset_size(mem.get(), H5T_VARIABLE);
      H5Tset_cset(mem.get(), H5Tget_cset(type.get()));  // HDF5 does not convert ASCII <-> UTF-8
      if (H5Aread(attr.get(), mem.get(), &value) >= 0 && value) {
        out[name] = value;
        H5free_memory(value);
      }
    } else {
      const std::size_t size = H5Tget_size(type.get());
      std::string value(size, '\0');
      Handle mem(H5Tcopy(H5T_C_S1), H5Tclose);
      H5Tset_size(mem.get(), size);
      H5Tset_cset(mem.get(), H5Tget_cset(type.get()));
      if (H5Aread(attr.get(), mem.get(), value.data()) >= 0) {
        value.resize(std::min(value.find('\0'), value.size()));
        out[name] = value;
      }
    }
  }
  return out;
}

void File::WriteStringAttribute(const std::string& object, const std::string& key, const std::string& value) {
  Handle obj(H5Oopen(id(), object.c_str(), H5P_DEFAULT), H5Oclose);
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.get(), H5T_VARIABLE);
  H5Tset_cset(type.get(), H5T_CSET_UTF8);
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attr(H5Acreate2(obj.get(), key.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  const char* text = value.c_str();
  if (!attr.valid() || H5Awrite(attr.get(), type.get(), &text) < 0)
    throw Error(Located(name_, object, "cannot write attribute " + key));
}

int64_t File::ReadInt64Attribute(const std::string& object, const std::string& key) const {
  if (H5Aexists_by_name(id(), object.c_str(), key.c_str(), H5P_DEFAULT) <= 0)
    throw Error(Located(name_, object, "missing attribute " + key));
  Handle attr(H5Aopen_by_name(id(), object.c_str(), key.c_str(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  Handle type(H5Aget_type(attr.get()), H5Tclose);
  Handle space(H5Aget_space(attr.get()), H5Sclose);
  if (H5Tget_class(type.get()) != H5T_INTEGER || H5Sget_simple_extent_npoints(space.get()) != 1)
    throw Error(Located(name_, object, "attribute " + key + " must be one integer"));
  int64_t value = 0;
  if (H5Aread(attr.get(), H5T_NATIVE_INT64, &value) < 0)
    throw Error(Located(name_, object, "cannot read attribute " + key));
  return value;
}

void File::WriteInt64Attribute(const std::string& object, const std::string& key, int64_t value) {
  Handle obj(H5Oopen(id(), object.c_str(), H5P_DEFAULT), H5Oclose);
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attr(H5Acreate2(obj.get(), key.c_str(), H5T_STD_I64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!attr.valid() || H5Awrite(attr.get(), H5T_NATIVE_INT64, &value) < 0)
    throw Error(Located(name_, object, "cannot write attribute " + key));
}

std::vector<std::string> File::Members(const std::string& group) const {
  std::vector<std::string> out;
  Handle g(H5Gopen2(id(), group.c_str(), H5P_DEFAULT), H5Gclose);
  if (!g.valid()) throw Error(Located(name_, group, "is not a group"));
  H5G_info_t info;
  H5Gget_info(g.get(), &info);
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    char name[256] = {0};
    H5Lget_name_by_idx(g.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, name, sizeof(name) - 1, H5P_DEFAULT);
    out.emplace_back(name);
  }
  return out;
}

void File::Flush() { H5Fflush(id(), H5F_SCOPE_GLOBAL); }

}  // namespace bead::h5
