#include "libbead/vision/frames_run.h"

#include "libbead/core/error.h"
#include "libbead/vision/frame_profile.h"
#include "libbead/vision/grey_frame.h"

namespace bead::vision {

FramesRun RunFromFrames(const std::vector<std::string>& paths, SensorModel sensor, double rate_hz,
                        const std::function<void(std::size_t, std::size_t)>& progress) {
  FramesRun out;
  ProfileBlock& b = out.run.profiles;
  b.shared_x = false;
  std::vector<float> x, z;
  StripeCentres stripe;
  for (std::size_t k = 0; k < paths.size(); ++k) {
    const std::string& path = paths[k];
    const cv::Mat frame = ReadGreyFrame(path);
    try {
      FrameProfile(frame, sensor, stripe, x, z);
    } catch (const Error& e) {
      throw Error(Located(path, "", e.what()));
    }
    if (k == 0) {
      out.lines = x.size(), b.points = out.lines;
      sensor.stripe.axis = stripe.axis;  // one axis for the run
    }
    if (x.size() != out.lines)
      throw Error(Located(path, "",
                          std::to_string(x.size()) + " lines, the first frame has " + std::to_string(out.lines) +
                              ": frames of one run share a size"));
    out.total += stripe.stats;
    b.t_s.push_back(static_cast<double>(k) / rate_hz);
    b.encoder.push_back(0);
    b.x_mm.insert(b.x_mm.end(), x.begin(), x.end());
    b.z_mm.insert(b.z_mm.end(), z.begin(), z.end());
    if (progress) progress(k + 1, paths.size());
  }
  for (float v : b.z_mm) out.points += v == v;
  out.run.attributes[kEncoderAttribute] = kEncoderAbsent;
  out.run.attributes["stripe"] = "axis=" + Name(sensor.stripe.axis) + " method=" + Name(sensor.stripe.method);
  out.stripe = sensor.stripe;
  return out;
}

}  // namespace bead::vision
