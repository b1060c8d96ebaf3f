// bead explain, series mode: any measured series (CSV or .mat) against a
// model of one input or several, the loop run on it.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <optional>

#include "libbead/core/error.h"
#include "libbead/explain/explain_json.h"
#include "libbead/explain/model_series.h"
#include "libbead/io/series_columns.h"
#include "tools/series_stretches.h"
#include "tools/explain_modes.h"

namespace bead::tools {
namespace {

// A series read: every input on the output's times.
struct ReadData {
  Series s;  // t, the first input, y
  std::vector<std::vector<double>> u;
};

ReadData Read(const ExplainArgs& a, const std::string& path) {
  ReadData d;
  if (a.inputs.size() > 1) {
    MultiSeries m = ReadMultiSeries(path, a.time, a.inputs, a.output);
    d.s = std::move(m.s);
    d.u = std::move(m.u);
    PrintFileNote(d.s.file_note);
    std::printf("%s: %zu rows where every input and the output are numbers\n", a.Shown(path).c_str(), d.s.t.size());
    return d;
  }
  d.s = ReadOneInputSeries(a.Names(), path, a.Shown(path));
  d.u = {d.s.u};
  return d;
}

// The data against the base model, with the named columns of its file as
// recorded channels on its clock.
explain::SeriesData Against(const ExplainArgs& a, const ReadData& r, const ProcessOn& on, const explain::BaseModel& m,
                            const std::string& path) {
  std::vector<explain::MoreInput> more;
  for (std::size_t k = 1; k < m.tfs.size(); ++k) more.push_back({a.inputs[k], m.tfs[k], r.u[k]});
  explain::SeriesData d = explain::ModelSeries(r.s.t, r.u[0], r.s.y, m.tfs[0], m.offset, on.segments, a.output, more);
  if (a.channels.empty() || a.no_channels) return d;
  const ChannelColumns c = ReadChannelColumns(path, a.time, a.channels);
  PrintFileNote(c.file_note);
  for (std::size_t k = 0; k < a.channels.size(); ++k) d.channels.push_back({a.channels[k], "", c.t, c.values[k]});
  return d;
}

}  // namespace

int ExplainSeriesMode(const ExplainArgs& a) {
  if (a.inputs.empty() || a.output.empty())
    throw CLI::RequiredError("CSV mode needs --input and --output (run mode needs --rig)");
  if (!a.flow_out.empty() || !a.pins.empty())
    throw CLI::ValidationError("--flow-out and --pins", "are for run mode (--rig)");
  CheckInputClocks(a.Names(), a.validate);
  explain::ExplainOptions options = a.Explain();
  const ReadData r = Read(a, a.data);
  const ProcessOn on = SeriesStretches(r.s, a.Shown(a.data), a.keep_off, "explain");
  const explain::BaseModel mdl = ModelFor(a, r.s.t, r.u, r.s.y, on.segments, a.Shown(a.data));
  const explain::SeriesData data = Against(a, r, on, mdl, a.data);
  std::optional<explain::SeriesData> other;
  if (!a.validate.empty()) {
    const ReadData v = Read(a, a.validate);
    other = Against(a, v, SeriesStretches(v.s, a.Shown(a.validate), a.keep_off, "explain"), mdl, a.validate);
    options.validation = &*other;
    std::printf("held-out data: %s (%zu rows)\n", a.Shown(a.validate).c_str(), v.s.t.size());
  }
  const explain::ExplainReport rep = explain::Explain(data, options);
  PrintReport(rep, a.output);
  std::vector<explain::NamedModel> more;
  for (std::size_t k = 1; k < mdl.tfs.size(); ++k) more.push_back({a.inputs[k], mdl.tfs[k]});
  nlohmann::json j = explain::ReportJson(rep, mdl.tfs[0], mdl.offset, mdl.source, more);
  j["mode"] = a.series_mode;
  j["compare"] = explain::CompareJson(data, rep);
  j["offset_from_run_counts"] = nullptr;  // no wheel in a plain series
  j["offset_from_run_ci95_counts"] = nullptr;
  j["rig_offset_counts"] = nullptr;
  nlohmann::json left = nlohmann::json::array();
  for (const auto& e : on.excluded)
    left.push_back({{"t_begin_s", e.t_begin_s}, {"t_end_s", e.t_end_s}, {"reason", e.reason}});
  j["excluded"] = left;
  WriteJson(a.out, j);
  return 0;
}

}  // namespace bead::tools
