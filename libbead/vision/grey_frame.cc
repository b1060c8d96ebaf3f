#include "libbead/vision/grey_frame.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "libbead/core/error.h"

namespace bead::vision {

cv::Mat ReadGreyFrame(const std::string& path) {
  cv::Mat frame = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (frame.empty()) throw Error(Located(path, "", "not an image OpenCV can read"));
  if (frame.channels() == 3) cv::cvtColor(frame, frame, cv::COLOR_BGR2GRAY);
  if (frame.channels() == 4) cv::cvtColor(frame, frame, cv::COLOR_BGRA2GRAY);
  if (frame.channels() != 1)
    throw Error(
        Located(path, "", std::to_string(frame.channels()) + " channels: expected grey, colour or colour with alpha"));
  return frame;
}

}  // namespace bead::vision
