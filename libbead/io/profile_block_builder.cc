#include "libbead/io/profile_block_builder.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "libbead/core/error.h"

namespace bead {

std::string ProfileBlockBuilder::Append(const char* noun, int64_t id, double t_s, int64_t encoder, float x_mm,
                                        float z_mm) {
  if (profiles_.empty() || id != current_id_) {
    if (seen_.count(id)) return std::string(noun) + " of profile " + std::to_string(id) + " are not together";
    seen_.insert({id, true});
    current_id_ = id;
    profiles_.push_back({t_s, encoder, {}, {}});
  } else if (t_s != profiles_.back().t || encoder != profiles_.back().encoder) {
    return "profile " + std::to_string(id) + " changes its t_s or encoder between " + noun;
  }
  profiles_.back().x.push_back(x_mm);
  profiles_.back().z.push_back(z_mm);
  return {};
}

void ProfileBlockBuilder::Add(const CsvReader& csv, int64_t id, double t_s, int64_t encoder, float x_mm, float z_mm) {
  const std::string why = Append("rows", id, t_s, encoder, x_mm, z_mm);
  if (!why.empty()) csv.Fail(why);
}

void ProfileBlockBuilder::Add(const std::string& file, const std::string& where, int64_t id, double t_s,
                              int64_t encoder, float x_mm, float z_mm) {
  const std::string why = Append("points", id, t_s, encoder, x_mm, z_mm);
  if (!why.empty()) throw Error(Located(file, where, why));
}

ProfileBlock ProfileBlockBuilder::Build(const std::string& file, const std::string& where) const {
  constexpr float kNaNf = std::numeric_limits<float>::quiet_NaN();
  ProfileBlock b;
  for (const auto& p : profiles_) b.points = std::max(b.points, p.x.size());
  b.shared_x = std::all_of(profiles_.begin(), profiles_.end(), [&](const Profile& p) {
    return p.x.size() == b.points && std::equal(p.x.begin(), p.x.end(), profiles_[0].x.begin(), [](float u, float v) {
             return u == v || (std::isnan(u) && std::isnan(v));
           });
  });
  if (b.shared_x && !profiles_.empty()) b.x_mm = profiles_[0].x;
  for (const auto& p : profiles_) {
    b.t_s.push_back(p.t);
    b.encoder.push_back(p.encoder);
    if (!b.shared_x) {
      b.x_mm.insert(b.x_mm.end(), p.x.begin(), p.x.end());
      b.x_mm.resize(b.x_mm.size() + (b.points - p.x.size()), kNaNf);
    }
    b.z_mm.insert(b.z_mm.end(), p.z.begin(), p.z.end());
    b.z_mm.resize(b.z_mm.size() + (b.points - p.z.size()), kNaNf);
  }
  ValidateProfileBlock(b, file, where);
  return b;
}

}  // namespace bead
