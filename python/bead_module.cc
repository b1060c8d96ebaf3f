// `import bead`: libbead from Python, NumPy arrays in and out. Each function
// is a thin call of the library (the same calls the `bead` commands make),
// with the GIL released while it works; arrays the library returns are
// handed to NumPy without a copy (the vector moves into the array's owner);
// arrays given are read in place when they are float32 and C-contiguous
// (otherwise NumPy converts them once). A bead::Error is raised as
// bead.Error carrying the tool's one-line message.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "libbead/archive/measure_run.h"
#include "libbead/archive/open_run.h"
#include "libbead/archive/run_flow.h"
#include "libbead/core/error.h"
#include "libbead/io/rig_yaml.h"
#include "libbead/io/run_archive.h"
#include "libbead/occlusion/occlusion_fit.h"
#include "libbead/profile/measure_block.h"
#include "python/numpy_owned.h"

namespace py = pybind11;
using namespace pybind11::literals;

namespace bead::python {

void AddPartArrays(RunArchive& run, py::dict& out);  // part.cc
void AddPartLogArrays(AcquisitionLog& l, py::dict& log);

namespace {

py::dict RunToDict(RunArchive&& run) {
  ProfileBlock& b = run.profiles;
  const auto n = static_cast<py::ssize_t>(b.size()), p = static_cast<py::ssize_t>(b.points);
  py::dict out;
  out["kind"] = "run";
  out["t_s"] = Owned(std::move(b.t_s), {n});
  if (run.part)
    AddPartArrays(run, out);
  else
    out["encoder"] = Owned(std::move(b.encoder), {n});
  out["x_mm"] = b.shared_x ? Owned(std::move(b.x_mm), {p}) : Owned(std::move(b.x_mm), {n, p});
  out["z_mm"] = Owned(std::move(b.z_mm), {n, p});
  if (run.log) {
    AcquisitionLog& l = *run.log;
    const auto m = static_cast<py::ssize_t>(l.size());
    py::dict log;
    log["t_s"] = Owned(std::move(l.t_s), {m});
    if (l.part())
      AddPartLogArrays(l, log);
    else
      log["encoder"] = Owned(std::move(l.encoder), {m});
    log["screw_rpm"] = Owned(std::move(l.screw_rpm), {m});
    if (!l.extruder_cmd_v.empty()) log["extruder_cmd_v"] = Owned(std::move(l.extruder_cmd_v), {m});
    if (!l.wheel_cmd_v.empty()) log["wheel_cmd_v"] = Owned(std::move(l.wheel_cmd_v), {m});
    for (LogChannel& c : l.channels) log[py::str(c.name)] = Owned(std::move(c.values), {m});
    out["log"] = log;
  } else {
    out["log"] = py::none();
  }
  out["attributes"] = run.attributes;
  return out;
}

py::dict ReadRun(const std::string& path) {
  RunArchive run;
  {
    py::gil_scoped_release free;
    run = IsPartScan(path) ? ReadPartScan(path) : ReadRunArchive(path);
  }
  return RunToDict(std::move(run));
}

// The geometry of a block of profiles given as arrays: z [N, P], x [P]
// (shared) or [N, P], both mm.
py::dict Measure(const py::array_t<float, py::array::c_style | py::array::forcecast>& x_mm,
                 const py::array_t<float, py::array::c_style | py::array::forcecast>& z_mm,
                 const std::vector<std::vector<double>>& reference_areas_mm, unsigned threads) {
  if (z_mm.ndim() != 2) throw Error("measure: z_mm must be 2-D, [profiles, points]");
  const std::size_t n = static_cast<std::size_t>(z_mm.shape(0)), p = static_cast<std::size_t>(z_mm.shape(1));
  const bool shared = x_mm.ndim() == 1;
  if (!(shared ? x_mm.shape(0) == z_mm.shape(1)
               : x_mm.ndim() == 2 && x_mm.shape(0) == z_mm.shape(0) && x_mm.shape(1) == z_mm.shape(1)))
    throw Error("measure: x_mm must be [points] or the shape of z_mm");
  if (reference_areas_mm.size() != 2 || reference_areas_mm[0].size() != 2 || reference_areas_mm[1].size() != 2)
    throw Error("measure: reference_areas_mm must be [[left_min, left_max], [right_min, right_max]] in mm");
  const ReferenceArea left{reference_areas_mm[0][0], reference_areas_mm[0][1]},
      right{reference_areas_mm[1][0], reference_areas_mm[1][1]};
  const float* x = x_mm.data();
  const float* z = z_mm.data();
  std::vector<BeadGeometry> g;
  {
    py::gil_scoped_release free;
    BlockOptions batch;
    batch.threads = threads;
    g = MeasureProfiles(
        n,
        [&](std::size_t i) {
          ProfileView v;
          v.x_mm = std::span<const float>(shared ? x : x + i * p, p);
          v.z_mm = std::span<const float>(z + i * p, p);
          return v;
        },
        left, right, ProfileOptions{}, batch);
  }
  return GeometryColumns(g);
}

// The rig file, its key warnings (a key one edit from a listed one) given
// to Python's warnings module.
Rig ReadRigWarning(const std::string& path) {
  const RigFile file = ReadRigFile(path);
  for (const std::string& w : file.warnings)
    if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) != 0) throw py::error_already_set();
  return file.rig;
}

py::dict MeasureRunColumns(const std::string& rig_path, const std::string& run_path, const std::string& occlusion,
                           unsigned threads) {
  std::vector<GeometryRow> rows;
  const Rig rig = ReadRigWarning(rig_path);
  {
    py::gil_scoped_release free;
    WorkerPool pool(threads);
    OpenedRun opened = OpenRun(run_path, pool, /*with_log=*/false);
    MeasureRunOptions options;
    options.occlusion = ParseOcclusionMode(occlusion);
    options.estimate = occlusion::EstimateOcclusion;
    MeasureRun(*opened.profiles, rig, pool, options, [&](const GeometryRow& r) { rows.push_back(r); });
  }
  return RowColumns(rows);
}

py::dict Flow(const std::string& rig_path, const std::string& run_path, const std::string& occlusion,
              unsigned threads) {
  FlowResult flow;
  const Rig rig = ReadRigWarning(rig_path);
  {
    py::gil_scoped_release free;
    WorkerPool pool(threads);
    RunFlowRequest request;
    request.measure.occlusion = ParseOcclusionMode(occlusion);
    request.measure.estimate = occlusion::EstimateOcclusion;
    request.keep = true;
    flow = std::move(MeasureRunFlow(run_path, rig, pool, request).flow);
  }
  return FlowColumns(flow);
}

}  // namespace

void AddModels(py::module_& m);   // models.cc
void AddExplain(py::module_& m);  // explain.cc
void AddPart(py::module_& m);     // part.cc

}  // namespace bead::python

PYBIND11_MODULE(bead, m) {
  using namespace bead::python;
  m.doc() =
      "libbead: bead cross-sections and volumetric flow from laser line profiles. Units: mm, s, mm^2, mm^3/s, RPM. "
      "Errors raise bead.Error with the tool's one-line message.";
  m.attr("__version__") = BEAD_VERSION;
  py::register_exception<bead::Error>(m, "Error", PyExc_RuntimeError);
  m.def("read_run", &ReadRun, "path"_a,
        "Read a run archive or a part scan (HDF5, docs/data-formats.md) into NumPy arrays.\n\n"
        "Returns a dict: kind ('run' or 'part'), t_s [N] (s), encoder [N] (counts; a run only), x_mm [P] or [N, P] "
        "(mm), z_mm [N, P] (mm), log (a dict of [M] arrays: t_s, encoder or a part's layer, path_mm and "
        "head_speed_mm_s, screw_rpm, and the recorded channels; None without a log), attributes; a part scan adds "
        "layer, path_mm, frame_z_mm, frame_x_mm [N] (mm).");
  m.def("measure", &Measure, "x_mm"_a, "z_mm"_a, "reference_areas_mm"_a, "threads"_a = 0,
        "Measure the bead of each profile of a block.\n\n"
        "x_mm: [P] shared by every profile or [N, P]; z_mm: [N, P] (mm; NaN: no point); reference_areas_mm: "
        "[[left_min, left_max], [right_min, right_max]] (mm), the bare surface either side. Returns a dict of [N] "
        "arrays: area_mm2, width_mm, height_mm, center_x_mm, area_sigma_mm2 (NaN where not valid), valid (bool), "
        "status (str), reference_rms_mm, threshold_mm. threads: 0 = all cores.");
  m.def("measure_run", &MeasureRunColumns, "rig"_a, "run"_a, "occlusion"_a = "pooled", "threads"_a = 0,
        "Measure every profile of a run archive as `bead measure --rig RIG RUN` does (occlusion: none, pooled or "
        "each).\n\nReturns the geometry CSV's columns as [N] arrays: profile, t_s (s), encoder (counts), area_mm2, "
        "width_mm, height_mm, area_corrected_mm2, valid, center_x_mm, reference_rms_mm, reference_points, "
        "threshold_mm, dropped_points, status, area_sigma_mm2, occlusion_bias_mm2, area_corrected_sigma_mm2 (mm, "
        "mm^2; NaN where the CSV is empty).");
  m.def("flow", &Flow, "rig"_a, "run"_a, "occlusion"_a = "pooled", "threads"_a = 0,
        "The run's volumetric flow Q = v A in extrusion time, as `bead flow` computes it.\n\nReturns the flow CSV's "
        "columns as [N] arrays: t_s (extrusion time, s), encoder, surface_speed_mm_s, area_mm2, area_corrected_mm2, "
        "flow_mm3_s, screw_rpm, profile, valid, occlusion_bias_mm2, area_corrected_sigma_mm2, flow_sigma_mm3_s; and "
        "total_volume_mm3.");
  AddModels(m);
  AddExplain(m);
  AddPart(m);
}
