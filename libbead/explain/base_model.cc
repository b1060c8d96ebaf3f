#include "libbead/explain/base_model.h"

#include "libbead/core/error.h"
#include "libbead/model/identify_multi.h"
#include "libbead/model/model_file.h"

namespace bead::explain {

BaseModel BaseModelFromFile(const std::string& path, std::size_t inputs) {
  const model::ModelFile f = model::ReadModelFile(path);
  if (f.tfs.size() != inputs)
    throw Error(Located(path, "",
                        "a model of " + std::to_string(f.tfs.size()) + " input(s), but the data give " +
                            std::to_string(inputs) +
                            " (run mode: the screw speed alone; CSV and .mat mode: one per --input column)"));
  BaseModel m;
  m.inputs = f.inputs;
  m.tfs = f.tfs;
  m.offset = f.offset;
  m.source = path;
  return m;
}

BaseModel IdentifyBaseModel(const std::vector<double>& t, const std::vector<std::vector<double>>& u,
                            const std::vector<double>& y, const std::vector<Segment>& segments,
                            const model::IdentifyOptions& options, const std::string& where) {
  const model::MultiInputModel im =
      model::IdentifyMultiInput(t, u, y, std::vector<model::IdentifyOptions>(u.size(), options), segments);
  if (!im.ok) throw Error(Located(where, "", "no model could be identified: " + im.reason));
  BaseModel m;
  for (const auto& part : im.inputs) {
    m.tfs.push_back(part.tf);
    if (part.delay_profile.ambiguous) m.warnings.push_back(part.delay_profile.note);
    if (part.delay_profile.at_limit) m.warnings.push_back(part.delay_profile.limit_note);
  }
  if (!im.note.empty()) m.warnings.push_back(im.note);
  m.offset = im.offset;
  m.identified = true;
  m.fit_percent = im.fit_percent;
  m.source = "identified on " + where + " (" + std::to_string(options.poles) + " poles, " +
             std::to_string(options.zeros) + " zeros" + (u.size() > 1 ? " per input" : "") +
             ", operating point and initial state estimated)";
  return m;
}

}  // namespace bead::explain
