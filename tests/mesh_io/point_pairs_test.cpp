// The correspondences file of cameras align --correspondences
// (mesh_io/point_pairs.h): six numbers a line, spaces, tabs or commas, '#'
// comments, a header line of words; errors name the file and the line.
#include "mesh_io/point_pairs.h"

#include <gtest/gtest.h>

#include "tests/mesh_io/test_files.h"

namespace texbake {
namespace {

TEST(PointPairs, SpacesCommasCommentsAndAHeader) {
  const std::string text =
      "model_x,model_y,model_z,mesh_x,mesh_y,mesh_z\r\n"
      "# picked in CloudCompare\n"
      "1, 2, 3, 4, 5, 6\r\n"
      "\n"
      "  -1.5\t0 2e-3   7 8 9  \n"
      "0;0;1;0;0;2\n";
  Expected<PointPairs> p = point_pairs_from_text(text, "pairs.csv");
  ASSERT_TRUE(p) << p.error().message;
  ASSERT_EQ(p->model.size(), 3u);
  ASSERT_EQ(p->mesh.size(), 3u);
  EXPECT_EQ(p->model[0].x, 1);
  EXPECT_EQ(p->model[0].z, 3);
  EXPECT_EQ(p->mesh[0].x, 4);
  EXPECT_EQ(p->mesh[0].z, 6);
  EXPECT_EQ(p->model[1].x, -1.5);
  EXPECT_EQ(p->model[1].z, 2e-3);
  EXPECT_EQ(p->mesh[1].y, 8);
  EXPECT_EQ(p->mesh[2].z, 2);
  EXPECT_EQ(p->lines, (std::vector<std::size_t>{3, 5, 6}));
}

TEST(PointPairs, ErrorsNameTheLine) {
  Expected<PointPairs> five = point_pairs_from_text("# pairs\n1 2 3 4 5 6\n1 2 3 4 5\n", "p.txt");
  ASSERT_FALSE(five);
  EXPECT_EQ(five.error().code, ErrorCode::kParse);
  EXPECT_EQ(five.error().message,
            "p.txt:3: expected 6 numbers (the model's x y z, then the mesh's), got 5");
  Expected<PointPairs> nan = point_pairs_from_text("1 2 3 4 5 6\n1 2 nan 4 5 6\n", "p.txt");
  ASSERT_FALSE(nan);
  EXPECT_EQ(nan.error().message, "p.txt:2: 'nan' is not a finite number");
  // Words after the first line are an error, not a header.
  Expected<PointPairs> words = point_pairs_from_text("1 2 3 4 5 6\nx y z a b c\n", "p.txt");
  ASSERT_FALSE(words);
  EXPECT_EQ(words.error().message, "p.txt:2: 'x' is not a finite number");
  // A first line mixing words and numbers is not a header either.
  EXPECT_FALSE(point_pairs_from_text("a 1 2 3 4 5\n", "p.txt"));
  // A header after comments and blank lines, and a byte order mark.
  Expected<PointPairs> late =
      point_pairs_from_text("\xEF\xBB\xBF# picked by hand\n\nx,y,z,X,Y,Z\n1,2,3,4,5,6\n", "p.txt");
  ASSERT_TRUE(late) << late.error().message;
  EXPECT_EQ(late->lines, (std::vector<std::size_t>{4}));
  Expected<PointPairs> bom = point_pairs_from_text(
      "\xEF\xBB\xBF"
      "1 2 3 4 5 6\n",
      "p.txt");
  ASSERT_TRUE(bom) << bom.error().message;
  EXPECT_EQ(bom->model[0].x, 1);
  // An empty file has no pairs (the fit says how many it needs).
  Expected<PointPairs> empty = point_pairs_from_text("", "p.txt");
  ASSERT_TRUE(empty);
  EXPECT_TRUE(empty->model.empty());
}

TEST(PointPairs, TheFileIsCheckedAndRead) {
  const std::filesystem::path dir = test::fresh_temp_dir("point_pairs");
  Expected<PointPairs> missing = read_point_pairs(dir / "none.txt");
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error().code, ErrorCode::kIo);
  EXPECT_NE(missing.error().message.find("no such file"), std::string::npos);
  test::write_text(dir / "p.txt", "0 0 0 1 1 1\n");
  Expected<PointPairs> p = read_point_pairs(dir / "p.txt");
  ASSERT_TRUE(p) << p.error().message;
  EXPECT_EQ(p->mesh[0].y, 1);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace texbake
