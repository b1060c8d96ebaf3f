#include "libbead/io/point_cloud.h"

#include <pcl/PCLPointCloud2.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <numeric>
#include <vector>

#include "libbead/core/error.h"
#include "libbead/io/atomic_file.h"
#include "libbead/io/profile_block_builder.h"

namespace bead {
namespace {

enum class CloudKind { kPly, kPcd, kOther };

CloudKind KindOf(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".ply" ? CloudKind::kPly : ext == ".pcd" ? CloudKind::kPcd : CloudKind::kOther;
}

// PCL prints its own reasons to the console; ours name the file instead.
void QuietPcl() { pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS); }

struct FieldSpec {
  const char* name;
  uint8_t type;
  uint32_t size;
};

constexpr FieldSpec kFields[] = {
    {"x", pcl::PCLPointField::FLOAT32, 4},       {"y", pcl::PCLPointField::FLOAT32, 4},
    {"z", pcl::PCLPointField::FLOAT32, 4},       {"z_sensor", pcl::PCLPointField::FLOAT32, 4},
    {"profile", pcl::PCLPointField::UINT32, 4},  {"t_s", pcl::PCLPointField::FLOAT64, 8},
    {"encoder", pcl::PCLPointField::FLOAT64, 8},
};

// One field of a loaded cloud, read as double whatever its stored type.
class FieldReader {
 public:
  FieldReader(const pcl::PCLPointCloud2& cloud, const pcl::PCLPointField& field)
      : cloud_(cloud), offset_(field.offset), type_(field.datatype) {}

  double operator()(std::size_t point) const {
    const uint8_t* p = cloud_.data.data() + point * cloud_.point_step + offset_;
    switch (type_) {
      case pcl::PCLPointField::INT8:
        return Load<int8_t>(p);
      case pcl::PCLPointField::UINT8:
        return Load<uint8_t>(p);
      case pcl::PCLPointField::INT16:
        return Load<int16_t>(p);
      case pcl::PCLPointField::UINT16:
        return Load<uint16_t>(p);
      case pcl::PCLPointField::INT32:
        return Load<int32_t>(p);
      case pcl::PCLPointField::UINT32:
        return Load<uint32_t>(p);
      case pcl::PCLPointField::INT64:
        return static_cast<double>(Load<int64_t>(p));
      case pcl::PCLPointField::UINT64:
        return static_cast<double>(Load<uint64_t>(p));
      case pcl::PCLPointField::FLOAT32:
        return Load<float>(p);
      case pcl::PCLPointField::FLOAT64:
        return Load<double>(p);
      default:
        return std::nan("");
    }
  }

 private:
  template <class T>
  static double Load(const uint8_t* p) {
    T v;
    std::memcpy(&v, p, sizeof v);
    return static_cast<double>(v);
  }
  const pcl::PCLPointCloud2& cloud_;
  uint32_t offset_;
  uint8_t type_;
};

std::string FieldNames(const pcl::PCLPointCloud2& cloud) {
  std::string all;
  for (const auto& f : cloud.fields) all += (all.empty() ? "" : ", ") + f.name;
  return all.empty() ? "none" : all;
}

FieldReader Field(const std::string& path, const pcl::PCLPointCloud2& cloud, const std::string& name,
                  const char* role) {
  for (const auto& f : cloud.fields) {
    if (f.name != name) continue;
    const std::size_t size = pcl::getFieldSize(f.datatype);
    if (size == 0 || f.count < 1 || f.offset + size > cloud.point_step)
      throw Error(Located(path, "field " + name, std::string("the ") + role + " field is not a number per point"));
    return FieldReader(cloud, f);
  }
  throw Error(
      Located(path, "",
              std::string("no field '") + name + "' for the " + role + " (the cloud has: " + FieldNames(cloud) + ")"));
}

}  // namespace

bool IsPointCloudPath(const std::string& path) { return KindOf(path) != CloudKind::kOther; }

void WritePointCloud(const std::string& path, const WheelCloud& c) {
  const CloudKind kind = KindOf(path);
  if (kind == CloudKind::kOther) throw Error(Located(path, "", "a point cloud is written as .ply or .pcd"));
  if (c.size() == 0) throw Error(Located(path, "", "no point to write: no profile had a reference line"));
  pcl::PCLPointCloud2 cloud;
  uint32_t offset = 0;
  const bool part = !c.layer.empty();
  if (part && c.layer.size() != c.size()) throw Error(Located(path, "", "internal: a layer for every point"));
  for (const FieldSpec& spec : kFields) {
    pcl::PCLPointField f;
    f.name = spec.name, f.offset = offset, f.datatype = spec.type, f.count = 1;
    cloud.fields.push_back(f);
    offset += spec.size;
  }
  if (part) {  // a part's cloud: each point's layer after the run's fields
    pcl::PCLPointField f;
    f.name = "layer", f.offset = offset, f.datatype = pcl::PCLPointField::FLOAT64, f.count = 1;
    cloud.fields.push_back(f);
    offset += 8;
  }
  cloud.point_step = offset;
  // PLY and PCD count a cloud's bytes in 32 bits (PCL's row_step).
  if (c.size() > UINT32_MAX / cloud.point_step)
    throw Error(Located(path, "",
                        std::to_string(c.size()) + " points are more than one PLY/PCD cloud holds (" +
                            std::to_string(UINT32_MAX / cloud.point_step) + "): thin the run (--every)"));
  cloud.width = static_cast<uint32_t>(c.size());
  cloud.height = 1;
  cloud.row_step = cloud.point_step * cloud.width;
  cloud.is_dense = true;  // only finite points are kept
  cloud.data.resize(static_cast<std::size_t>(cloud.row_step));
  for (std::size_t i = 0; i < c.size(); ++i) {
    uint8_t* p = cloud.data.data() + i * cloud.point_step;
    const double t = c.t_s[i], encoder = static_cast<double>(c.encoder[i]);
    std::memcpy(p + 0, &c.x_mm[i], 4);
    std::memcpy(p + 4, &c.s_mm[i], 4);
    std::memcpy(p + 8, &c.z_mm[i], 4);
    std::memcpy(p + 12, &c.z_sensor_mm[i], 4);
    std::memcpy(p + 16, &c.profile[i], 4);
    std::memcpy(p + 20, &t, 8);
    std::memcpy(p + 28, &encoder, 8);
    if (part) {
      const double layer = static_cast<double>(c.layer[i]);
      std::memcpy(p + 36, &layer, 8);
    }
  }
  QuietPcl();
  AtomicFile out(path);
  const Eigen::Vector4f origin = Eigen::Vector4f::Zero();
  const Eigen::Quaternionf orientation = Eigen::Quaternionf::Identity();
  int rc = 0;
  if (kind == CloudKind::kPly) {
    pcl::PLYWriter writer;
    rc = writer.writeBinary(out.temp_path(), cloud, origin, orientation, /*use_camera=*/false);
  } else {
    pcl::PCDWriter writer;
    rc = writer.writeBinaryCompressed(out.temp_path(), cloud, origin, orientation);
  }
  if (rc != 0) throw Error(Located(path, "", "PCL could not write the cloud (is the folder writable?)"));
  out.Commit();
}

ImportedRun ReadPointCloud(const std::string& path, const ImportColumns& c) {
  CheckImportColumns(path, c, false);
  const CloudKind kind = KindOf(path);
  if (kind == CloudKind::kOther) throw Error(Located(path, "", "a point cloud is read from .ply or .pcd"));
  if (!std::filesystem::is_regular_file(path)) throw Error(Located(path, "", "no such file"));
  QuietPcl();
  pcl::PCLPointCloud2 cloud;
  const int rc = kind == CloudKind::kPly ? pcl::io::loadPLYFile(path, cloud) : pcl::io::loadPCDFile(path, cloud);
  const char* what = kind == CloudKind::kPly ? "PLY" : "PCD";
  if (rc < 0) throw Error(Located(path, "", std::string("not a ") + what + " file PCL can read"));
  const std::size_t n = static_cast<std::size_t>(cloud.width) * cloud.height;
  if (n == 0) throw Error(Located(path, "", "the cloud holds no point"));
  if (cloud.data.size() < n * cloud.point_step)
    throw Error(Located(path, "", "the cloud's data is shorter than its header says"));
  const bool by_row = c.profile.empty();
  if (by_row && cloud.height < 2)
    throw Error(Located(path, "",
                        "name the field that numbers the scan lines (--profile-column); the cloud is not "
                        "organized in rows and has the fields: " +
                            FieldNames(cloud)));
  const FieldReader time = Field(path, cloud, c.time, "time");
  const FieldReader x = Field(path, cloud, c.x, "x");
  const FieldReader z = Field(path, cloud, c.z, "z");
  const bool has_encoder = !c.encoder.empty();
  const FieldReader encoder = has_encoder ? Field(path, cloud, c.encoder, "encoder") : x;
  const std::vector<double> line = [&] {
    std::vector<double> v(n);
    if (by_row) {
      for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<double>(i / cloud.width);
      return v;
    }
    const FieldReader f = Field(path, cloud, c.profile, "scan line");
    for (std::size_t i = 0; i < n; ++i)
      if (!std::isfinite(v[i] = f(i)))
        throw Error(
            Located(path, "point " + std::to_string(i), "the scan line field '" + c.profile + "' is not finite"));
    return v;
  }();
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return line[a] < line[b]; });

  const float sign = c.z_is_distance ? -1.0f : 1.0f;
  ImportedRun result;
  ProfileBlockBuilder builder;
  int64_t id = -1;
  double t = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = order[k];
    const std::string where = "point " + std::to_string(i);
    if (k == 0 || line[i] != line[order[k - 1]]) {
      ++id;
      t = time(i) * c.time_scale;
      if (!std::isfinite(t)) throw Error(Located(path, where, "the time field '" + c.time + "' is not finite"));
    }
    int64_t counter = 0;
    if (has_encoder) {
      const double e = encoder(i);
      if (!(std::isfinite(e) && e == std::floor(e) && std::fabs(e) < 9.0e15))
        throw Error(Located(path, where, "the encoder field '" + c.encoder + "' is not a whole number"));
      counter = static_cast<int64_t>(e);
    }
    builder.Add(path, where, id, t, counter, static_cast<float>(x(i)), sign * static_cast<float>(z(i)));
  }
  result.rows = n;
  result.run.profiles = builder.Build(path, "scan lines");
  result.run.attributes["imported_from"] = std::filesystem::path(path).filename().string();
  if (!has_encoder) result.run.attributes[kEncoderAttribute] = kEncoderAbsent;
  return result;
}

}  // namespace bead
