#include "libbead/io/part_datasets.h"

#include <cmath>

#include "libbead/core/error.h"
#include "libbead/io/run_archive.h"

namespace bead {
namespace {

void CheckFinite(const std::vector<double>& v, const std::string& file, const std::string& dataset) {
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      throw Error(Located(file, dataset + "[" + std::to_string(i) + "]", "must be a finite number (mm)"));
}

// Layers from 0 that never fall: the profiles of a layer lie together.
void CheckLayers(const std::vector<int64_t>& layer, const std::string& file, const std::string& dataset, bool ordered) {
  for (std::size_t i = 0; i < layer.size(); ++i) {
    const std::string at = dataset + "[" + std::to_string(i) + "]";
    if (layer[i] < 0) throw Error(Located(file, at, "a layer counts from 0 (got " + std::to_string(layer[i]) + ")"));
    if (ordered && i > 0 && layer[i] < layer[i - 1])
      throw Error(Located(file, at,
                          "layer " + std::to_string(layer[i]) + " after layer " + std::to_string(layer[i - 1]) +
                              ": a part scan's profiles come layer by layer, in the order they were measured"));
  }
}

}  // namespace

void CheckLength(std::size_t got, std::size_t want, const std::string& file, const std::string& dataset,
                 const std::string& other) {
  if (got != want)
    throw Error(
        Located(file, dataset,
                "length mismatch: " + std::to_string(got) + " values, but " + other + " has " + std::to_string(want)));
}

bool IsPartLogDataset(const std::string& name) {
  return name == "layer" || name == "path_mm" || name == "head_speed_mm_s";
}

void ValidatePartPlaces(const PartPlaces& p, std::size_t profiles, const std::string& file, const std::string& where) {
  const std::string t_name = where + "/t_s";
  CheckLength(p.layer.size(), profiles, file, where + "/layer", t_name);
  CheckLength(p.path_mm.size(), profiles, file, where + "/path_mm", t_name);
  CheckLength(p.frame_z_mm.size(), profiles, file, where + "/frame_z_mm", t_name);
  CheckLength(p.frame_x_mm.size(), profiles, file, where + "/frame_x_mm", t_name);
  CheckLayers(p.layer, file, where + "/layer", true);
  CheckFinite(p.path_mm, file, where + "/path_mm");
  CheckFinite(p.frame_z_mm, file, where + "/frame_z_mm");
  CheckFinite(p.frame_x_mm, file, where + "/frame_x_mm");
}

PartPlaces ReadPartPlaces(const h5::File& f, std::size_t profiles) {
  PartPlaces p;
  p.layer = f.ReadInt64("/profiles/layer", {1}).data;
  p.path_mm = f.ReadDouble("/profiles/path_mm", {1}).data;
  p.frame_z_mm = f.ReadDouble("/profiles/frame_z_mm", {1}).data;
  if (f.Exists("/profiles/frame_x_mm"))
    p.frame_x_mm = f.ReadDouble("/profiles/frame_x_mm", {1}).data;
  else
    p.frame_x_mm.assign(p.layer.size(), 0.0);
  ValidatePartPlaces(p, profiles, f.name(), "/profiles");
  return p;
}

void WritePartPlaces(h5::File& f, const PartPlaces& p) {
  const hsize_t n = p.size();
  f.Write("/profiles/layer", p.layer, {n});
  f.Write("/profiles/path_mm", p.path_mm, {n});
  f.Write("/profiles/frame_z_mm", p.frame_z_mm, {n});
  f.Write("/profiles/frame_x_mm", p.frame_x_mm, {n});
}

void ValidatePartLog(const AcquisitionLog& log, const std::string& file, const std::string& where) {
  const std::string t_name = where + "/t_s";
  CheckLength(log.layer.size(), log.size(), file, where + "/layer", t_name);
  CheckLength(log.path_mm.size(), log.size(), file, where + "/path_mm", t_name);
  if (!log.head_speed_mm_s.empty())
    CheckLength(log.head_speed_mm_s.size(), log.size(), file, where + "/head_speed_mm_s", t_name);
  CheckLayers(log.layer, file, where + "/layer", false);
  CheckFinite(log.path_mm, file, where + "/path_mm");
  CheckFinite(log.head_speed_mm_s, file, where + "/head_speed_mm_s");
}

void ReadPartLog(const h5::File& f, AcquisitionLog& log) {
  log.layer = f.ReadInt64("/log/layer", {1}).data;
  log.path_mm = f.ReadDouble("/log/path_mm", {1}).data;
  if (f.Exists("/log/head_speed_mm_s")) log.head_speed_mm_s = f.ReadDouble("/log/head_speed_mm_s", {1}).data;
  ValidatePartLog(log, f.name(), "/log");
}

void WritePartLog(h5::File& f, const AcquisitionLog& log) {
  const hsize_t m = log.size();
  f.Write("/log/layer", log.layer, {m});
  f.Write("/log/path_mm", log.path_mm, {m});
  if (!log.head_speed_mm_s.empty()) f.Write("/log/head_speed_mm_s", log.head_speed_mm_s, {m});
}

}  // namespace bead
