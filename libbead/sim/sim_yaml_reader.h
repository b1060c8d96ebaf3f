// The simulation config's YAML reader (sim_config_yaml.cc's): typed keys
// with ranges, sections whose unknown keys are refused, every error naming
// the file, line and key. Internal to sim/; not installed.
#pragma once

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "libbead/core/error.h"
#include "libbead/model/transfer_function.h"

namespace bead::sim {

class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}
  const std::string& file() const { return file_; }

  [[noreturn]] void Fail(const YAML::Node& n, const std::string& key, const std::string& what) const {
    const std::string place = n.IsDefined() ? "line " + std::to_string(n.Mark().line + 1) + ": " + key : key;
    throw Error(Located(file_, place, what));
  }

  // A key or a name: plain text (a YAML sequence or mapping there is an error).
  std::string Text(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) Fail(n, key, "must be plain text");
    return n.Scalar();
  }

  // Section `key` of `parent`, checking its keys are among `known`.
  YAML::Node Section(const YAML::Node& parent, const std::string& key, std::set<std::string> known) const {
    YAML::Node s = parent[key];
    if (!s.IsDefined() || s.IsNull()) return YAML::Node(YAML::NodeType::Undefined);
    if (!s.IsMap()) Fail(s, key, "must be a mapping");
    for (const auto& kv : s) {
      const std::string k = Text(kv.first, key + ".<key>");
      if (!known.count(k)) Fail(kv.first, key + "." + k, "unknown key (misspelt?)");
    }
    return s;
  }

  void Get(const YAML::Node& sec, const std::string& path, const std::string& key, double& out, double lo = -INFINITY,
           double hi = INFINITY) const {
    if (!sec.IsDefined()) return;
    const YAML::Node n = sec[key];
    if (!n.IsDefined() || n.IsNull()) return;
    double v = 0;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      Fail(n, path + key, "must be a number");
    }
    if (!std::isfinite(v) || v < lo || v > hi) {
      std::ostringstream msg;
      msg << "must be a finite number in [" << lo << ", " << hi << "], got " << n.Scalar();
      Fail(n, path + key, msg.str());
    }
    out = v;
  }

  template <typename Int>
  void GetInt(const YAML::Node& sec, const std::string& path, const std::string& key, Int& out, double lo,
              double hi) const {
    double v = static_cast<double>(out);
    Get(sec, path, key, v, lo, hi);
    if (v != std::floor(v)) Fail(sec[key], path + key, "must be a whole number");
    out = static_cast<Int>(v);
  }

  void GetBool(const YAML::Node& sec, const std::string& path, const std::string& key, bool& out) const {
    if (!sec.IsDefined() || !sec[key].IsDefined()) return;
    try {
      out = sec[key].as<bool>();
    } catch (const YAML::Exception&) {
      Fail(sec[key], path + key, "must be true or false");
    }
  }

  void GetList(const YAML::Node& sec, const std::string& path, const std::string& key, std::vector<double>& out) const {
    if (!sec.IsDefined() || !sec[key].IsDefined()) return;
    const YAML::Node n = sec[key];
    if (!n.IsSequence() || n.size() == 0) Fail(n, path + key, "must be a non-empty list of numbers");
    out.clear();
    for (const auto& e : n) {
      try {
        out.push_back(e.as<double>());
      } catch (const YAML::Exception&) {
        Fail(e, path + key, "must be a list of numbers");
      }
      if (!std::isfinite(out.back())) Fail(e, path + key, "must hold finite numbers");
    }
  }

  template <typename E>
  void GetEnum(const YAML::Node& sec, const std::string& path, const std::string& key, E& out,
               const std::vector<std::pair<std::string, E>>& names) const {
    if (!sec.IsDefined() || !sec[key].IsDefined()) return;
    const std::string v = Text(sec[key], path + key);
    std::string all;
    for (const auto& [name, value] : names) {
      if (name == v) {
        out = value;
        return;
      }
      all += (all.empty() ? "" : ", ") + name;
    }
    Fail(sec[key], path + key, "is '" + v + "', expected one of: " + all);
  }

  void GetTf(const YAML::Node& sec, const std::string& path, const std::string& key,
             model::TransferFunction& tf) const {
    const YAML::Node n = Section(sec, key, {"num", "den", "delay_s"});
    if (!n.IsDefined()) return;
    GetList(n, path + key + ".", "num", tf.num);
    GetList(n, path + key + ".", "den", tf.den);
    Get(n, path + key + ".", "delay_s", tf.delay_s, 0.0, 60.0);
    try {
      tf.Validate();
    } catch (const Error& e) {
      Fail(n, path + key, e.what());
    }
  }

 private:
  std::string file_;
};

}  // namespace bead::sim
