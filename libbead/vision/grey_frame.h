// A camera frame from an image file, as one channel of grey levels (8- or
// 16-bit, or float as stored); colour is made grey. Throws bead::Error
// naming the file when OpenCV cannot read it.
#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace bead::vision {

cv::Mat ReadGreyFrame(const std::string& path);

}  // namespace bead::vision
