// The files of a job and the rule that no output is an input or another
// output (SPEC section 12): job_inputs, job_outputs, camera_files,
// layers_files, colmap_workspace_files and check_distinct_files.
#include <sys/stat.h>

#include <cstdio>
#include <string>
#include <system_error>
#include <vector>

#include "bake/texbake/run.h"
#include "mesh_io/layers_json.h"
#include "mesh_io/mesh_files.h"
#include "texbake/texbake.h"

namespace texbake {

namespace {

namespace fs = std::filesystem;

// What makes two paths one file: the device and inode of an existing file
// (after links), and for any path its absolute form with links, "." and
// ".." resolved as far as it exists. Worked out once per path, as a job may
// name thousands of photos.
struct FileId {
  bool exists = false;
  dev_t device = 0;
  ino_t inode = 0;
  fs::path normal;
};

FileId file_id(const fs::path& p) {
  FileId id;
  struct stat st {};
  if (::stat(p.c_str(), &st) == 0) {
    id.exists = true;
    id.device = st.st_dev;
    id.inode = st.st_ino;
  }
  std::error_code ec;
  fs::path normal = fs::weakly_canonical(fs::absolute(p, ec), ec);
  id.normal = ec ? p.lexically_normal() : normal;
  return id;
}

bool same(const FileId& a, const FileId& b) {
  return (a.exists && b.exists && a.device == b.device && a.inode == b.inode) ||
         a.normal == b.normal;
}

Error same_file_error(const NamedFile& out, const NamedFile& other, const char* why) {
  return make_error(ErrorCode::kInvalidArgument, out.name + " " + out.path.string() + " and " +
                                                     other.name + " " + other.path.string() +
                                                     " are the same file: " + why);
}

void add(std::vector<NamedFile>& files, const std::string& name, const fs::path& path) {
  if (!path.empty()) files.push_back({name, path});
}

void append(std::vector<NamedFile>& files, std::vector<NamedFile> more) {
  files.insert(files.end(), std::make_move_iterator(more.begin()),
               std::make_move_iterator(more.end()));
}

}  // namespace

std::vector<NamedFile> camera_files(const fs::path& cameras, const fs::path& images,
                                    const std::string& name, const fs::path& masks) {
  std::vector<NamedFile> files;
  if (cameras.empty()) return files;
  std::error_code ec;
  if (fs::is_directory(cameras, ec)) {
    // The model's files (mesh_io/colmap_model.h), and points3D, which a
    // workspace holds beside them.
    for (const char* stem : {"cameras", "images", "points3D"}) {
      for (const char* ext : {".txt", ".bin"}) {
        const fs::path p = cameras / (std::string(stem) + ext);
        if (fs::exists(p, ec)) add(files, name, p);
      }
    }
  } else {
    add(files, name, cameras);
  }
  if (Expected<std::vector<Photo>> photos = read_cameras(cameras, images)) {
    for (const Photo& photo : *photos) add(files, "a photo of " + name, photo.path);
    if (!masks.empty()) {
      for (const Photo& photo : *photos) {
        add(files, "the mask of a photo of " + name, mask_file(masks, photo.name));
      }
    }
  }
  return files;
}

std::vector<NamedFile> layers_files(const fs::path& layers) {
  std::vector<NamedFile> files;
  if (layers.empty()) return files;
  add(files, "--layers", layers);
  Expected<LayersSpec> spec = read_layers_file(layers);
  if (!spec) return files;
  for (std::size_t i = 0; i < spec->layers.size(); ++i) {
    const LayerSpec& layer = spec->layers[i];
    const std::string key = "layers[" + std::to_string(i) + "]";
    add(files, key + ".proxy_file", layer.proxy_file);
    add(files, key + ".texture", layer.texture);
    add(files, key + ".mask", layer.mask);
    append(files, camera_files(layer.cameras, layer.images, key + ".cameras", layer.masks));
  }
  return files;
}

std::string colmap_view_name(int k) {
  char name[32];
  std::snprintf(name, sizeof name, "view_%02d.png", k);
  return name;
}

std::vector<NamedFile> colmap_workspace_files(const fs::path& dir, int views) {
  std::vector<NamedFile> files;
  if (dir.empty()) return files;
  for (int k = 0; k < views; ++k) add(files, "--colmap", dir / "images" / colmap_view_name(k));
  for (const char* model : {"cameras.txt", "images.txt"}) {
    add(files, "--colmap", dir / "sparse" / "0" / model);
  }
  return files;
}

std::vector<NamedFile> job_inputs(const JobFileNames& job) {
  std::vector<NamedFile> files;
  add(files, "MESH", job.mesh);
  // Its material libraries, textures, buffers and images (mesh_io/mesh_files.h).
  for (const fs::path& named : mesh_named_files(job.mesh)) add(files, "a file MESH names:", named);
  add(files, "--texture", job.texture);
  add(files, "--proxy-file", job.proxy_file);
  append(files, camera_files(job.cameras, job.images, "--cameras", job.masks));
  append(files, layers_files(job.layers));
  add(files, "JOBS", job.manifest);
  return files;
}

std::vector<NamedFile> job_outputs(const JobFileNames& job) {
  std::vector<NamedFile> files;
  if (!job.output.empty()) {
    const std::vector<fs::path> written =
        job.atlas ? atlas_files(job.output, job.write) : std::vector<fs::path>{job.output};
    add(files, "-o", written[0]);
    if (written.size() == 3) {
      add(files, "the material of -o", written[1]);
      add(files, "the atlas image of -o", written[2]);
    }
  }
  add(files, "--report", job.report);
  add(files, "--results", job.results);
  return files;
}

Status check_distinct_files(const std::vector<NamedFile>& inputs,
                            const std::vector<NamedFile>& outputs) {
  std::vector<FileId> in_ids, out_ids;
  in_ids.reserve(inputs.size());
  for (const NamedFile& in : inputs)
    in_ids.push_back(in.path.empty() ? FileId{} : file_id(in.path));
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const NamedFile& out = outputs[i];
    out_ids.push_back(out.path.empty() ? FileId{} : file_id(out.path));
    if (out.path.empty()) continue;
    for (std::size_t j = 0; j < inputs.size(); ++j) {
      if (!inputs[j].path.empty() && same(out_ids[i], in_ids[j])) {
        return same_file_error(out, inputs[j], "texbake never overwrites an input");
      }
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (!outputs[j].path.empty() && same(out_ids[i], out_ids[j])) {
        return same_file_error(out, outputs[j], "two outputs cannot share one file");
      }
    }
  }
  return ok_status();
}

Status check_job_files(const JobFileNames& job) {
  return check_distinct_files(job_inputs(job), job_outputs(job));
}

}  // namespace texbake
