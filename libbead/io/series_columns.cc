#include "libbead/io/series_columns.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "libbead/core/error.h"
#include "libbead/io/csv_reader.h"
#include "libbead/io/mat_file.h"

namespace bead {
namespace {

// Columns by name (an empty name: the row number as time); rows with a
// missing or non-numeric value are skipped and counted.
struct Columns {
  std::vector<std::vector<double>> v;
  int skipped = 0;
  std::string first_skip;  // "line 5, column 'w': 'N/A'"
  std::string file_note;   // a .mat file's unusable contents
};

// The row rule of both sources: a row whose values all came is kept, the
// others counted; the time (the first value) must increase, else `fail`
// throws naming the row.
template <class Fail>
void AddRow(Columns& out, const std::vector<double>& v, bool ok, bool first_is_time, const Fail& fail) {
  if (!ok) {
    ++out.skipped;
    return;
  }
  if (first_is_time && !out.v[0].empty() && !(v[0] > out.v[0].back()))
    fail("does not increase (" + std::to_string(out.v[0].back()) + " then " + std::to_string(v[0]) + ")");
  for (std::size_t k = 0; k < v.size(); ++k) out.v[k].push_back(v[k]);
}

bool IsMat(const std::string& path) {
  return path.size() > 4 &&
         (path.compare(path.size() - 4, 4, ".mat") == 0 || path.compare(path.size() - 4, 4, ".MAT") == 0);
}

// The same from a .mat file: each name a vector variable, all of one
// length (one clock); NaN and infinite values skipped as gaps. What the
// file holds and a reader cannot use is said once on stdout.
Columns ReadMat(const std::string& path, const std::vector<std::string>& names, bool first_is_time) {
  const MatContents mat = ReadMatVectors(path);
  std::string note;
  if (!mat.skipped.empty()) {
    std::string list;
    for (const auto& s : mat.skipped) list += (list.empty() ? "" : "; ") + s;
    note = path + ": skipped what is no numeric vector: " + list;
  }
  std::vector<const MatVector*> vars;
  std::size_t n = 0;
  for (const auto& name : names) {
    if (name.empty()) {
      vars.push_back(nullptr);
      continue;
    }
    const MatVector* v = mat.Find(name);
    if (!v) throw Error(Located(path, "", "no numeric vector '" + name + "' (vectors: " + mat.Names() + ")"));
    if (n != 0 && v->values.size() != n) {
      std::string sizes;
      for (const MatVector* w : vars)
        if (w) sizes += "'" + w->name + "' " + std::to_string(w->values.size()) + ", ";
      throw Error(Located(path, "",
                          "'" + name + "' holds " + std::to_string(v->values.size()) + " values, " + sizes +
                              "not the same: they are on different clocks; name the input's with "
                              "--input-time and the output's with --output-time"));
    }
    n = v->values.size();
    vars.push_back(v);
  }
  Columns out;
  out.file_note = note;
  out.v.resize(names.size());
  std::vector<double> v(names.size());
  for (std::size_t i = 0; i < n; ++i) {
    bool ok = true;
    for (std::size_t k = 0; k < vars.size() && ok; ++k) {
      v[k] = vars[k] ? vars[k]->values[i] : double(i);
      if (!std::isfinite(v[k])) {
        ok = false;
        if (out.first_skip.empty())
          out.first_skip = "element " + std::to_string(i + 1) + " of '" + names[k] + "': not finite";
      }
    }
    AddRow(out, v, ok, first_is_time, [&](const std::string& why) {
      throw Error(Located(path, "", "'" + names[0] + "' " + why + " at element " + std::to_string(i + 1)));
    });
  }
  return out;
}

Columns Read(const std::string& path, const std::vector<std::string>& names, bool first_is_time) {
  if (IsMat(path)) return ReadMat(path, names, first_is_time);
  CsvReader csv(path);
  const auto header = csv.Header({}, "data CSV's");
  auto find = [&](const std::string& name) -> long {
    if (name.empty()) return -1;
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return static_cast<long>(i);
    std::string all;
    for (const auto& h : header) all += (all.empty() ? "" : ", ") + h;
    throw Error(Located(path, "line 1", "no column '" + name + "' (columns: " + all + ")"));
  };
  std::vector<long> cols;
  for (const auto& n : names) cols.push_back(find(n));
  Columns out;
  out.v.resize(names.size());
  long row = 0;
  std::vector<double> v(names.size());
  while (csv.Next()) {
    ++row;
    bool ok = true;
    for (std::size_t k = 0; k < cols.size() && ok; ++k) {
      if (cols[k] < 0) {
        v[k] = static_cast<double>(row - 1);
        continue;
      }
      const auto c = static_cast<std::size_t>(cols[k]);
      if (c >= csv.columns() || csv.Empty(c)) {
        ok = false;
        if (out.first_skip.empty())
          out.first_skip = "line " + std::to_string(row + 1) + ", column '" + names[k] + "': empty";
        break;
      }
      char* end = nullptr;
      const std::string f(csv.Field(c));
      v[k] = std::strtod(f.c_str(), &end);
      ok = end && *end == '\0' && std::isfinite(v[k]);
      if (!ok && out.first_skip.empty())
        out.first_skip = "line " + std::to_string(row + 1) + ", column '" + names[k] + "': '" + f.substr(0, 40) +
                         "' is not a finite number";
    }
    AddRow(out, v, ok, first_is_time, [&](const std::string& why) { csv.Fail("time " + why); });
  }
  return out;
}

}  // namespace

Series ReadColumns(const std::string& path, const std::string& time, const std::string& input,
                   const std::string& output) {
  return ReadSeries({path, time, input, output, "", ""});
}

Series ReadSeries(const SeriesSpec& given) {
  SeriesSpec spec = given;
  // An input on its own clock in the same file (a .mat's variables).
  if (spec.input_path.empty() && !spec.input_time.empty()) spec.input_path = spec.path;
  Series s;
  if (spec.input_path.empty()) {
    Columns c = Read(spec.path, {spec.time, spec.input, spec.output}, true);
    s.t = std::move(c.v[0]);
    s.u = std::move(c.v[1]);
    s.y = std::move(c.v[2]);
    s.skipped = c.skipped;
    s.first_skip = c.first_skip;
    s.file_note = c.file_note;
  } else {
    if (spec.time.empty() || spec.input_time.empty())
      throw Error(
          Located(spec.input_path, "", "an input on its own clock needs --output-time (or --time) and --input-time"));
    Columns out = Read(spec.path, {spec.time, spec.output}, true);
    Columns in = Read(spec.input_path, {spec.input_time, spec.input}, true);
    if (in.v[0].empty()) throw Error(Located(spec.input_path, "", "no usable input rows"));
    s.skipped = out.skipped;
    s.first_skip = out.first_skip;
    s.file_note = out.file_note;
    int before = 0;
    for (std::size_t i = 0; i < out.v[0].size(); ++i) {
      const double t = out.v[0][i];
      const auto it = std::upper_bound(in.v[0].begin(), in.v[0].end(), t);
      if (it == in.v[0].begin()) {
        ++before;
        continue;
      }
      s.t.push_back(t);
      s.u.push_back(in.v[1][static_cast<std::size_t>(it - in.v[0].begin()) - 1]);
      s.y.push_back(out.v[1][i]);
    }
    char buf[256];
    std::snprintf(
        buf, sizeof buf, "input '%s' from %s (%zu rows, %d skipped) held at each of the output's times%s",
        spec.input.c_str(), spec.input_path.c_str(), in.v[0].size(), in.skipped,
        before ? (", " + std::to_string(before) + " output rows before the first input left out").c_str() : "");
    s.note = buf;
  }
  if (s.t.size() < 20)
    throw Error(Located(
        spec.path, "",
        "fewer than 20 usable rows (" + std::to_string(s.t.size()) + ")" +
            (s.skipped ? "; " + std::to_string(s.skipped) + " skipped, the first at " + s.first_skip : std::string())));
  return s;
}

ChannelColumns ReadChannelColumns(const std::string& path, const std::string& time,
                                  const std::vector<std::string>& names) {
  std::vector<std::string> all = {time};
  all.insert(all.end(), names.begin(), names.end());
  Columns c = Read(path, all, true);
  if (c.v[0].size() < 2)
    throw Error(
        Located(path, "", "fewer than 2 rows where every channel (" + std::to_string(names.size()) + ") is a number"));
  ChannelColumns out;
  out.file_note = c.file_note;
  out.t = std::move(c.v[0]);
  for (std::size_t k = 1; k < c.v.size(); ++k) out.values.push_back(std::move(c.v[k]));
  return out;
}

// Several inputs: every column on the data's own clock, the rows where all
// of them (and the output) are numbers.
MultiSeries ReadMultiSeries(const std::string& path, const std::string& time, const std::vector<std::string>& inputs,
                            const std::string& output) {
  std::vector<std::string> names = inputs;
  names.push_back(output);
  ChannelColumns c = ReadChannelColumns(path, time, names);
  MultiSeries m;
  m.s.file_note = c.file_note;
  m.s.t = c.t;
  m.s.y = std::move(c.values.back());
  c.values.pop_back();
  m.s.u = c.values[0];
  m.u = std::move(c.values);
  return m;
}

}  // namespace bead
