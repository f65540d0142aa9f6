// Results of texbake/texbake.h: Stats worked out by hand, the atlas pipeline
// against its stages called one by one, and the writers.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "bake/atlas/dilate.h"
#include "tests/bake/bunny_earth.h"
#include "tests/bake/test_meshes.h"
#include "tests/bake/texbake/api_test_util.h"
#include "texbake/texbake.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;

// The unit square at z = 0 as a 4 x 4 grid (25 vertices, 32 triangles),
// plus one unreferenced vertex above it and one face repeating a vertex
// (degenerate): built so that every count is known by hand.
MeshData square_with_issues() {
  MeshData m;
  test::append_grid(m, 4, 4, [](double s, double t) {
    return Float3{static_cast<float>(s), static_cast<float>(t), 0};
  });
  test::faces_from_triangles(m);
  m.positions.push_back({0.5f, 0.5f, 1});  // vertex 25: no face
  m.face_vertices.insert(m.face_vertices.end(), {0, 0, 1});
  m.face_offsets.push_back(static_cast<uint32_t>(m.face_vertices.size()));
  triangulate_faces(m);
  return m;
}

Proxy unit_plane() {
  return make_proxy(PlaneParams{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}).value();
}

// read_mesh with RunOptions: the same mesh and issues as the plain reader,
// on one thread or all; errors as the plain reader gives them.
TEST(ApiResults, ReadMeshInAnArenaGivesThePlainReadersMesh) {
  const std::filesystem::path path = test::shared_data("bunny00.off");
  Expected<LoadedMesh> plain = read_mesh(path);
  ASSERT_TRUE(plain.has_value()) << plain.error().message;
  for (int threads : {1, 0}) {
    RunOptions run;
    run.threads = threads;
    Expected<LoadedMesh> m = read_mesh(path, run);
    ASSERT_TRUE(m.has_value()) << m.error().message;
    EXPECT_EQ(m->mesh.triangles, plain->mesh.triangles);
    EXPECT_EQ(m->mesh.triangle_face, plain->mesh.triangle_face);
    EXPECT_EQ(m->issues.degenerate_triangles, plain->issues.degenerate_triangles);
    EXPECT_EQ(m->issues.unreferenced_vertices, plain->issues.unreferenced_vertices);
    EXPECT_EQ(m->issues.non_manifold_edges, plain->issues.non_manifold_edges);
  }
  Expected<LoadedMesh> missing = read_mesh(path.parent_path() / "no_such_mesh.off", RunOptions{});
  ASSERT_FALSE(missing.has_value());
  EXPECT_EQ(category(missing.error()), ErrorCategory::kInput);
  EXPECT_NE(missing.error().message.find("no_such_mesh.off"), std::string::npos);
}

TEST(ApiResults, VertexStatsByHand) {
  const MeshData m = square_with_issues();
  ASSERT_EQ(m.triangles.size(), 32u);
  const Rgba c{0.25f, 0.5f, 0.75f, 1};
  const Image img = test::constant_image(4, 4, c);
  Expected<VertexColors> baked = bake_vertex_colors(m, img.view(), unit_plane());
  ASSERT_TRUE(baked) << baked.error().message;
  const Counts& n = baked->stats.counts;
  EXPECT_EQ(n.vertices, 26u);
  EXPECT_EQ(n.triangles, 32u);
  EXPECT_EQ(n.degenerate_triangles, 1u);
  EXPECT_EQ(n.unreferenced_vertices, 1u);
  // 16 area samples for each of the 25 grid vertices, one bilinear sample
  // at the vertex in no triangle; nothing blocks the +z rays.
  EXPECT_EQ(n.samples, 25u * 16 + 1);
  EXPECT_EQ(n.occluded, 0u);
  EXPECT_EQ(n.undefined, 0u);
  EXPECT_EQ(n.outside, 0u);
  EXPECT_EQ(n.filled, 0u);
  ASSERT_EQ(baked->colors.size(), 26u);
  for (const Rgba& v : baked->colors) {
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(v[k], c[k], 1e-6);
  }
  const Timings& t = baked->stats.timings;
  EXPECT_GE(t.bake, 0);
  EXPECT_GE(t.total, t.bake + t.fill + t.scene_build);
  EXPECT_EQ(t.uv_layout, 0);
  EXPECT_TRUE(baked->stats.warnings.empty());
}

TEST(ApiResults, TakingTheImageOverGivesTheSameColours) {
  const test::BunnyEarth* be = test::bunny_earth();
  ASSERT_TRUE(be);
  Expected<VertexColors> viewed = bake_vertex_colors(be->mesh, be->earth.view(), be->proxy);
  Image copy = be->earth;
  Expected<VertexColors> owned = bake_vertex_colors(be->mesh, std::move(copy), be->proxy);
  ASSERT_TRUE(viewed && owned);
  EXPECT_TRUE(viewed->colors == owned->colors);
}

TEST(ApiResults, AtlasEqualsItsStagesCalledOneByOne) {
  // Second method: generate the layout with the default padding's gutter
  // (bunny_earth.h, as documented), bake_atlas on it.
  const test::BunnyEarth* be = test::bunny_earth();
  ASSERT_TRUE(be);
  constexpr int kSize = 128;
  AtlasOptions ao;
  ao.bake.size = kSize;
  Expected<Atlas> atlas = bake_atlas_texture(be->mesh, be->earth.view(), be->proxy, ao);
  ASSERT_TRUE(atlas) << atlas.error().message;
  Expected<MeshData> layout = test::bunny_with_generated_uvs(be->mesh, kSize);
  ASSERT_TRUE(layout);
  Expected<AtlasBakeResult> manual = bake_atlas(*layout, be->earth.view(), be->proxy, ao.bake);
  ASSERT_TRUE(manual);

  EXPECT_EQ(atlas->uv.used, UvLayout::kGenerate);  // the bunny has no UVs
  EXPECT_GT(atlas->uv.charts, 0u);
  EXPECT_FALSE(atlas->repeat_u);
  EXPECT_EQ(atlas->image.width, kSize);
  EXPECT_TRUE(atlas->image.pixels == manual->atlas.pixels);
  EXPECT_EQ(atlas->mesh.uvs.size(), layout->uvs.size());
  const Counts& c = atlas->stats.counts;
  EXPECT_EQ(c.texels, manual->counts.texels);
  EXPECT_EQ(c.samples, manual->counts.texels * 4);
  EXPECT_EQ(c.padded, manual->counts.padded);
  EXPECT_EQ(c.vertices, be->mesh.vertex_count());  // the input's, not the layout's
  EXPECT_GT(atlas->stats.timings.uv_layout, 0);
}

// The consuming overload: the same atlas and counts as the const one, the
// caller's mesh emptied on return (after a success or a refusal); with --uv
// mesh the input's arrays themselves become the atlas mesh's.
TEST(ApiResults, TakingTheMeshOverGivesTheSameAtlas) {
  const test::BunnyEarth* be = test::bunny_earth();
  ASSERT_TRUE(be);
  auto same_uvs = [](const MeshData& a, const MeshData& b) {
    if (a.uvs.size() != b.uvs.size() || a.corner_uv != b.corner_uv) return false;
    for (std::size_t i = 0; i < a.uvs.size(); ++i) {
      if (a.uvs[i].u != b.uvs[i].u || a.uvs[i].v != b.uvs[i].v) return false;
    }
    return true;
  };
  AtlasOptions ao;
  ao.bake.size = 64;
  Expected<Atlas> kept = bake_atlas_texture(be->mesh, be->earth.view(), be->proxy, ao);
  ASSERT_TRUE(kept) << kept.error().message;
  MeshData given = be->mesh;
  Expected<Atlas> taken = bake_atlas_texture(std::move(given), be->earth.view(), be->proxy, ao);
  ASSERT_TRUE(taken) << taken.error().message;
  EXPECT_TRUE(given.positions.empty() && given.triangles.empty() && given.face_vertices.empty());
  EXPECT_TRUE(taken->image.pixels == kept->image.pixels);
  EXPECT_TRUE(same_uvs(taken->mesh, kept->mesh));
  EXPECT_EQ(taken->mesh.triangles, kept->mesh.triangles);
  auto same_counts = [](const Counts& a, const Counts& b) {
    return a.vertices == b.vertices && a.triangles == b.triangles &&
           a.degenerate_triangles == b.degenerate_triangles &&
           a.unreferenced_vertices == b.unreferenced_vertices && a.samples == b.samples &&
           a.occluded == b.occluded && a.undefined == b.undefined && a.outside == b.outside &&
           a.texels == b.texels && a.padded == b.padded;
  };
  EXPECT_TRUE(same_counts(taken->stats.counts, kept->stats.counts));

  // --uv mesh on the laid-out mesh: the same atlas, the input moved in whole.
  ao.uv = UvLayout::kMesh;
  Expected<Atlas> kept_mesh = bake_atlas_texture(kept->mesh, be->earth.view(), be->proxy, ao);
  ASSERT_TRUE(kept_mesh) << kept_mesh.error().message;
  MeshData with_uvs = kept->mesh;
  const Float3* positions = with_uvs.positions.data();
  const Float2* uvs = with_uvs.uvs.data();
  Expected<Atlas> taken_mesh =
      bake_atlas_texture(std::move(with_uvs), be->earth.view(), be->proxy, ao);
  ASSERT_TRUE(taken_mesh) << taken_mesh.error().message;
  EXPECT_TRUE(with_uvs.positions.empty() && with_uvs.uvs.empty());
  EXPECT_EQ(taken_mesh->mesh.positions.data(), positions);  // moved, not copied
  EXPECT_EQ(taken_mesh->mesh.uvs.data(), uvs);
  EXPECT_TRUE(taken_mesh->image.pixels == kept_mesh->image.pixels);
  EXPECT_TRUE(same_uvs(taken_mesh->mesh, kept->mesh));
  EXPECT_EQ(taken_mesh->mesh.face_vertices, kept->mesh.face_vertices);
  EXPECT_TRUE(same_counts(taken_mesh->stats.counts, kept_mesh->stats.counts));

  // A call refused before the layout still takes the mesh.
  MeshData refused = be->mesh;
  AtlasOptions bad = ao;
  bad.bake.size = 0;
  EXPECT_FALSE(bake_atlas_texture(std::move(refused), be->earth.view(), be->proxy, bad));
  EXPECT_TRUE(refused.positions.empty());
}

TEST(ApiResults, ProxyLayoutOfASphereRepeatsInU) {
  const test::BunnyEarth* be = test::bunny_earth();
  ASSERT_TRUE(be);
  AtlasOptions ao;
  ao.uv = UvLayout::kProxy;
  ao.bake.size = 32;
  Expected<Atlas> atlas = bake_atlas_texture(be->mesh, be->earth.view(), be->proxy, ao);
  ASSERT_TRUE(atlas) << atlas.error().message;
  EXPECT_EQ(atlas->uv.used, UvLayout::kProxy);
  EXPECT_TRUE(atlas->repeat_u);
  EXPECT_GT(atlas->uv.cut_triangles, 0u);  // the seam crosses the bunny
}

TEST(ApiResults, RenderCountsItsRaysByHand) {
  const test::BunnyEarth* be = test::bunny_earth();
  ASSERT_TRUE(be);
  RenderOptions ro = test::bunny_view(20, 3);
  ro.views = 2;
  Expected<Rendered> r = render_mesh(be->mesh, GreySource{}, ro);
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r->image.width, 40);  // two views side by side
  EXPECT_EQ(r->rays.primary_rays, 20u * 20 * 2 * 3);
  EXPECT_EQ(r->rays.shadow_rays, 0u);
  EXPECT_EQ(r->stats.counts.triangles, be->mesh.triangles.size());
  EXPECT_GT(r->stats.timings.scene_build, 0);
}

class ApiWrite : public ::testing::Test {
 protected:
  fs::path dir = fs::temp_directory_path() / ("texbake_api_write_" + std::to_string(::getpid()));
  void SetUp() override {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }
};

TEST_F(ApiWrite, AtlasFilesByHand) {
  WriteOptions o;
  EXPECT_EQ(atlas_files(dir / "a.obj", o),
            (std::vector<fs::path>{dir / "a.obj", dir / "a.mtl", dir / "a.png"}));
  o.format = AtlasFormat::kExr;
  EXPECT_EQ(atlas_files(dir / "a.OBJ", o),
            (std::vector<fs::path>{dir / "a.OBJ", dir / "a.mtl", dir / "a.exr"}));
  EXPECT_EQ(atlas_files(dir / "a.glb", o), (std::vector<fs::path>{dir / "a.glb"}));
}

TEST_F(ApiWrite, VertexColoursReadBackAsTheir8BitValues) {
  const MeshData m = test::uv_sphere({0, 0, 0}, 1, 3, 4);
  std::vector<Rgba> colors(m.vertex_count());
  for (std::size_t v = 0; v < colors.size(); ++v) colors[v] = {v / 10.0f, 0.5f, 1, 1};
  for (const char* name : {"c.ply", "c.obj"}) {
    ASSERT_TRUE(write_vertex_colors(dir / name, m, colors)) << name;
    Expected<LoadedMesh> back = read_mesh(dir / name);
    ASSERT_TRUE(back) << back.error().message;
    ASSERT_EQ(back->mesh.vertex_colors.size(), colors.size()) << name;
    for (std::size_t v = 0; v < colors.size(); ++v) {
      EXPECT_NEAR(back->mesh.vertex_colors[v][0], std::round(v / 10.0 * 255) / 255, 1e-6) << name;
    }
  }
  ASSERT_TRUE(write_vertex_colors(dir / "c.glb", m, colors));
  EXPECT_TRUE(fs::exists(dir / "c.glb"));
}

TEST_F(ApiWrite, WriterUsageErrorsWriteNothing) {
  const MeshData m = test::uv_sphere({0, 0, 0}, 1, 3, 4);
  std::vector<Rgba> colors(m.vertex_count(), Rgba{1, 0, 0, 1});
  WriteOptions ascii;
  ascii.ascii = true;
  Status s = write_vertex_colors(dir / "a.obj", m, colors, ascii);
  ASSERT_FALSE(s);
  EXPECT_EQ(category(s.error()), ErrorCategory::kUsage);
  s = write_vertex_colors(dir / "a.xyz", m, colors);
  ASSERT_FALSE(s);
  EXPECT_EQ(category(s.error()), ErrorCategory::kUsage);
  colors.pop_back();
  s = write_vertex_colors(dir / "a.ply", m, colors);
  ASSERT_FALSE(s);
  EXPECT_EQ(category(s.error()), ErrorCategory::kUsage);

  Atlas atlas;
  atlas.mesh = m;
  atlas.image = test::constant_image(2, 2, {1, 0, 0, 1});
  WriteOptions exr;
  exr.format = AtlasFormat::kExr;
  s = write_atlas(dir / "a.glb", atlas, exr);
  ASSERT_FALSE(s);
  EXPECT_EQ(category(s.error()), ErrorCategory::kUsage);
  s = write_atlas(dir / "a.ply", atlas);
  ASSERT_FALSE(s);
  EXPECT_EQ(category(s.error()), ErrorCategory::kUsage);
  EXPECT_TRUE(fs::is_empty(dir));
}

TEST_F(ApiWrite, AnAtlasWritesExactlyItsFiles) {
  const test::BunnyEarth* be = test::bunny_earth();
  ASSERT_TRUE(be);
  AtlasOptions ao;
  ao.bake.size = 32;
  Expected<Atlas> atlas = bake_atlas_texture(be->mesh, be->earth.view(), be->proxy, ao);
  ASSERT_TRUE(atlas);
  WriteOptions o;
  o.format = AtlasFormat::kPng16;
  ASSERT_TRUE(write_atlas(dir / "bunny.obj", *atlas, o));
  std::vector<fs::path> written;
  for (const auto& e : fs::directory_iterator(dir)) written.push_back(e.path());
  std::sort(written.begin(), written.end());
  std::vector<fs::path> expected = atlas_files(dir / "bunny.obj", o);
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(written, expected);
  Expected<Image> png = read_image(dir / "bunny.png");
  ASSERT_TRUE(png);
  EXPECT_EQ(png->width, 32);
}

}  // namespace
}  // namespace texbake
