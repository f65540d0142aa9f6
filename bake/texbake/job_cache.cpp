// JobCache (texbake/job.h): the last mesh and texture, for the next job.
#include <mutex>
#include <optional>
#include <system_error>
#include <utility>
#include <vector>

#include "bake/texbake/job.h"
#include "bake/trace/embree_scene.h"
#include "mesh_io/mesh_files.h"

namespace texbake {

namespace fs = std::filesystem;

namespace {

// A file as it is now: its path, size and modification time. Two stamps
// are equal when the file was not changed between them (as far as the file
// system tells: a write within the clock's resolution that keeps the size
// is not seen; ext4 and the like keep nanoseconds).
struct FileStamp {
  fs::path path;
  std::uintmax_t size = 0;
  fs::file_time_type time{};
  bool operator==(const FileStamp&) const = default;
};

// The stamps of `path` and of the files it names (mesh_named_files: an
// OBJ's materials and textures, a glTF's buffers and images); nullopt when
// one cannot be read (the reader then reports why, uncached).
std::optional<std::vector<FileStamp>> stamps(const fs::path& path, bool named) {
  std::vector<fs::path> files{path};
  if (named) {
    for (fs::path& f : mesh_named_files(path)) files.push_back(std::move(f));
  }
  std::vector<FileStamp> out;
  for (const fs::path& f : files) {
    std::error_code ec;
    const fs::path canonical = fs::weakly_canonical(f, ec);
    if (ec) return std::nullopt;
    FileStamp s{canonical, fs::file_size(canonical, ec), {}};
    if (ec) return std::nullopt;
    s.time = fs::last_write_time(canonical, ec);
    if (ec) return std::nullopt;
    out.push_back(std::move(s));
  }
  return out;
}

bool same_read(const ImageReadOptions& a, const ImageReadOptions& b) {
  return a.color_space == b.color_space && a.cache_mb == b.cache_mb &&
         a.memory_copies == b.memory_copies && a.mip_levels == b.mip_levels &&
         a.linear_working == b.linear_working;
}

}  // namespace

struct JobCache::State {
  std::mutex mutex;
  std::vector<FileStamp> mesh_stamp;
  std::shared_ptr<const LoadedMesh> mesh;
  std::shared_ptr<const EmbreeScene> scene;  // of `mesh`, once a job asked for it
  std::vector<FileStamp> image_stamp;
  ImageReadOptions image_options;
  std::shared_ptr<const Image> image;
  Counts counts;
};

JobCache::JobCache() : state_(std::make_unique<State>()) {}
JobCache::~JobCache() = default;

Expected<std::shared_ptr<const LoadedMesh>> JobCache::mesh(const fs::path& path,
                                                           const RunOptions& run) {
  State& s = *state_;
  const std::optional<std::vector<FileStamp>> now = stamps(path, true);
  std::lock_guard<std::mutex> lock(s.mutex);
  if (now && s.mesh && *now == s.mesh_stamp) {
    ++s.counts.mesh_hits;
    return s.mesh;
  }
  s.scene.reset();
  s.mesh.reset();  // before reading the next one: one mesh in memory, not two
  s.mesh_stamp.clear();
  ++s.counts.mesh_reads;
  Expected<LoadedMesh> read = read_mesh(path, run);
  if (!read) return read.error();
  auto shared = std::make_shared<const LoadedMesh>(std::move(read).value());
  // Stamped before the read: a file changed during it is read again next time.
  if (now) s.mesh = shared, s.mesh_stamp = *now;
  return shared;
}

Expected<std::shared_ptr<const Image>> JobCache::image(const fs::path& path,
                                                       const ImageReadOptions& options) {
  State& s = *state_;
  const std::optional<std::vector<FileStamp>> now = stamps(path, false);
  std::lock_guard<std::mutex> lock(s.mutex);
  if (now && s.image && *now == s.image_stamp && same_read(options, s.image_options)) {
    ++s.counts.image_hits;
    return s.image;
  }
  s.image.reset();
  s.image_stamp.clear();
  ++s.counts.image_reads;
  Expected<Image> read = read_image(path, options);
  if (!read) return read.error();
  auto shared = std::make_shared<const Image>(std::move(read).value());
  if (now) s.image = shared, s.image_stamp = *now, s.image_options = options;
  return shared;
}

Expected<std::shared_ptr<const EmbreeScene>> JobCache::scene(
    const std::shared_ptr<const LoadedMesh>& mesh, bool* built) {
  State& s = *state_;
  if (built) *built = false;
  std::lock_guard<std::mutex> lock(s.mutex);
  if (!mesh || mesh != s.mesh || mesh->mesh.triangles.size() > kSceneKeepTriangles) {
    return std::shared_ptr<const EmbreeScene>{};
  }
  if (s.scene) {
    ++s.counts.scene_hits;
    return s.scene;
  }
  // The quality the per-vertex bake builds with (bake_vertex_sample).
  Expected<EmbreeScene> scene = EmbreeScene::build(mesh->mesh, BuildQuality::kLow);
  if (!scene) return scene.error();
  ++s.counts.scene_builds;
  if (built) *built = true;
  s.scene = std::make_shared<const EmbreeScene>(std::move(scene).value());
  return s.scene;
}

void JobCache::drop_scene() {
  std::lock_guard<std::mutex> lock(state_->mutex);
  state_->scene.reset();
}

JobCache::Counts JobCache::counts() const {
  std::lock_guard<std::mutex> lock(state_->mutex);
  return state_->counts;
}

}  // namespace texbake
