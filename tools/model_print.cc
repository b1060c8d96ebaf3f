#include "tools/model_print.h"

#include <cstdio>

#include "libbead/model/model_file.h"

namespace bead::tools {
namespace {

void PrintTransferFunction(const model::IdentifiedModel& m, const model::IdentifyOptions& o, const char* indent) {
  std::printf("%smodel: (%s) / (%s) * exp(-%.4g s)%s\n", indent, model::PolynomialText(m.tf.num).c_str(),
              model::PolynomialText(m.tf.den).c_str(), m.tf.delay_s, o.delay_s ? " (delay fixed)" : "");
  std::printf("%sDC gain %.6g; poles:", indent, m.tf.DcGain());
  for (std::size_t k = 0; k < m.poles_real.size(); ++k) std::printf(" %.4g%+.4gi", m.poles_real[k], m.poles_imag[k]);
  std::printf("\n");
  if (m.process.valid) {
    std::printf("%sprocess form: K %.5g, Tp", indent, m.process.K);
    for (double tp : m.process.Tp_s) std::printf(" %.4g", tp);
    std::printf(" s, Tz %.4g s, Td %.4g s\n", m.process.Tz_s, m.process.Td_s);
  }
}

void PrintBasins(const model::DelayProfile& p, const char* indent) {
  for (std::size_t k = 0; k < p.basins.size(); ++k)
    std::printf("%sdelay basin %zu: %.4f s, loss %.5g%s\n", indent, k + 1, p.basins[k].delay_s,
                p.basins[k].refined_loss, k == 0 ? " (chosen)" : "");
  if (p.ambiguous) std::printf("%swarning: %s\n", indent, p.note.c_str());
  if (p.at_limit) std::printf("%swarning: %s\n", indent, p.limit_note.c_str());
}

}  // namespace

void PrintModel(const model::IdentifiedModel& m, const model::IdentifyOptions& o) {
  PrintTransferFunction(m, o, "");
  if (o.estimate_offset)
    std::printf("operating point: input %.5g, output %.5g (y = %.5g + G(s) u)\n", m.input_level, m.output_level,
                m.offset);
  PrintBasins(m.delay_profile, "");
}

void PrintMultiInputModel(const model::MultiInputModel& m, const std::vector<model::IdentifyOptions>& o,
                          const std::vector<std::string>& inputs) {
  for (std::size_t i = 0; i < m.inputs.size(); ++i) {
    std::printf("input %zu, %s (operating point %.5g):\n", i + 1, inputs[i].c_str(), m.inputs[i].input_level);
    PrintTransferFunction(m.inputs[i], o[i], "  ");
    PrintBasins(m.inputs[i].delay_profile, "  ");
  }
  if (o[0].estimate_offset) std::printf("operating point: y = %.5g + sum_i G_i(s) u_i\n", m.offset);
  std::printf("backfitting: %d sweep%s, %s; the inputs correlate at most %.3f\n", m.sweeps, m.sweeps == 1 ? "" : "s",
              m.converged ? "converged" : "NOT converged", m.max_input_correlation);
  if (!m.note.empty()) std::printf("warning: %s\n", m.note.c_str());
}

}  // namespace bead::tools
