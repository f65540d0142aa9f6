// Internal to the camera file readers (nerfstudio_json.cpp,
// metashape_xml.cpp, meshroom_sfm.cpp): how they print a number in a
// message and word a parse error.
#pragma once

#include <cstdio>
#include <string>

#include "mapping/error.h"

namespace texbake::camera_text {

// A number as a message shows it: 9 significant digits (a float's round
// trip), no trailing zeros.
inline std::string show(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

// "WHERE: WHAT", a parse error.
inline Error fail(const std::string& where, const std::string& what) {
  return make_error(ErrorCode::kParse, where + ": " + what);
}

}  // namespace texbake::camera_text
