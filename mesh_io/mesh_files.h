// The files a mesh file names, which its reader opens beside it: an OBJ's
// material libraries (`mtllib`) and their textures (`map_Kd`), a .gltf's
// or a .glb's external buffers and images. A job lists them as inputs, so that no
// output overwrites them (texbake/texbake.h, job_inputs).
#pragma once

#include <filesystem>
#include <vector>

namespace texbake {

// The files `mesh` names, resolved as the readers resolve them (an OBJ's
// names relative to its folder, a .gltf's or .glb's (its JSON chunk) URIs
// percent-decoded and relative to its folder; data: URIs name no file). Files that do not exist are
// left out. Never fails: a file that cannot be scanned names nothing here,
// and its reader reports why. Other formats name no file.
std::vector<std::filesystem::path> mesh_named_files(const std::filesystem::path& mesh);

}  // namespace texbake
