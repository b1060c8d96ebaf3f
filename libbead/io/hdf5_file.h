// Thin RAII layer over the HDF5 C API: open/create files, read and write
// numeric datasets with their shape, string attributes. Every failure is a
// bead::Error naming the file and the dataset. HDF5's own error printing is
// switched off; we say what is wrong ourselves.
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace bead::h5 {

// An owned hid_t, closed with the right H5*close.
class Handle {
 public:
  Handle() = default;
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~Handle() { reset(); }
  Handle(Handle&& o) noexcept : id_(o.id_), close_(o.close_) { o.id_ = H5I_INVALID_HID; }
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = o.id_;
      close_ = o.close_;
      o.id_ = H5I_INVALID_HID;
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  void reset();

 private:
  hid_t id_ = H5I_INVALID_HID;
  herr_t (*close_)(hid_t) = nullptr;
};

enum class Kind { kFloat, kInteger };

template <typename T>
struct Array {
  std::vector<T> data;
  std::vector<hsize_t> dims;
};

class File {
 public:
  static File OpenRead(const std::string& path);
  static File OpenReadWrite(const std::string& path);  // to add to a file in place (tests, tools)
  static File Create(const std::string& path, const std::string& display_name);

  const std::string& name() const { return name_; }
  hid_t id() const { return handle_.get(); }
  bool Exists(const std::string& object) const;

  // Opens a dataset after checking its type class, rank (one of `ranks`)
  // and declared shape (against what the file stores); `dims` gets the shape.
  Handle OpenDataset(const std::string& dataset, std::initializer_list<int> ranks, Kind kind,
                     std::vector<hsize_t>& dims) const;

  // Reads a dataset of the given kind (any width; HDF5 converts), checking
  // its rank is one of `ranks`.
  Array<double> ReadDouble(const std::string& dataset, std::initializer_list<int> ranks) const;
  Array<float> ReadFloat(const std::string& dataset, std::initializer_list<int> ranks) const;
  Array<int64_t> ReadInt64(const std::string& dataset, std::initializer_list<int> ranks) const;

  void CreateGroup(const std::string& group);
  void Write(const std::string& dataset, const std::vector<double>& data, const std::vector<hsize_t>& dims);
  void Write(const std::string& dataset, const std::vector<float>& data, const std::vector<hsize_t>& dims);
  void Write(const std::string& dataset, const std::vector<int64_t>& data, const std::vector<hsize_t>& dims);

  std::map<std::string, std::string> ReadStringAttributes(const std::string& object) const;
  void WriteStringAttribute(const std::string& object, const std::string& key, const std::string& value);
  int64_t ReadInt64Attribute(const std::string& object, const std::string& key) const;
  void WriteInt64Attribute(const std::string& object, const std::string& key, int64_t value);
  // Names of the members of a group.
  std::vector<std::string> Members(const std::string& group) const;
  void Flush();

 private:
  template <typename T>
  Array<T> Read(const std::string& dataset, std::initializer_list<int> ranks, Kind kind, hid_t mem_type) const;
  void CheckStoredSize(hid_t ds, hid_t type, const std::vector<hsize_t>& dims, const std::string& dataset) const;
  template <typename T>
  void WriteImpl(const std::string& dataset, const std::vector<T>& data, const std::vector<hsize_t>& dims,
                 hid_t file_type, hid_t mem_type);

  std::string name_;
  Handle handle_;
};

}  // namespace bead::h5
