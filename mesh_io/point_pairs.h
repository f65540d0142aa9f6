// Point correspondences for `texbake cameras align --correspondences FILE`
// (a model without sparse points, or one the automatic fit cannot place):
// each pair is a point in the model's frame and the same point in the
// mesh's frame, as picked by hand in a viewer (CloudCompare's point-pair
// picking, MeshLab's PickPoints, Blender's 3D cursor) or taken from markers.
//
// The file is text: one pair per line, six numbers, the model's point then
// the mesh's (x y z X Y Z), separated by spaces, tabs or commas (so a CSV
// export reads as is); empty lines and lines starting with '#' are skipped,
// and so are a first line (after those) that holds no number (a CSV
// header) and a UTF-8 byte order mark.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string_view>
#include <vector>

#include "mapping/error.h"
#include "mapping/vec.h"

namespace texbake {

struct PointPairs {
  std::vector<Vec3> model;         // in the model's frame
  std::vector<Vec3> mesh;          // the same points in the mesh's frame
  std::vector<std::size_t> lines;  // each pair's line in the file, from 1
};

// Parses the text of a correspondences file; `where` names it in errors.
// Errors (kParse): "WHERE:LINE: expected 6 numbers (the model's x y z, then
// the mesh's), got N", "WHERE:LINE: 'TOKEN' is not a finite number".
Expected<PointPairs> point_pairs_from_text(std::string_view text, const std::string& where);

// Reads a correspondences file (check_text_file first: a regular file of
// at most 16 MiB). Errors: kIo (missing, unreadable), kParse (as above).
Expected<PointPairs> read_point_pairs(const std::filesystem::path& path);

}  // namespace texbake
