// The check every malformed-input test makes: reading `path` throws
// bead::Error whose message starts with the file and holds `expect`.
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "libbead/core/error.h"

namespace bead::test {

inline void ExpectRejected(const std::string& path, const std::string& expect, const std::function<void()>& read) {
  try {
    read();
    ADD_FAILURE() << path << " was accepted";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(path + ": ", 0), 0u) << path << ": " << what;
    EXPECT_NE(what.find(expect), std::string::npos) << path << ": " << what;
  }
}

// The one-line message `f` throws as bead::Error; "" when it throws none.
inline std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace bead::test
