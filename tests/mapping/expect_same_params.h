// Member-by-member equality of two ProxyParams, written out per kind (not
// through the schema's tables, which are under test): shared by the schema
// and the proxy JSON tests.
#pragma once

#include <gtest/gtest.h>

#include <variant>

#include "mapping/proxy.h"

namespace texbake::testing_params {

inline void expect_same_params(const ProxyParams& got, const ProxyParams& want) {
  ASSERT_EQ(got.index(), want.index());
  if (const auto* w = std::get_if<SphereParams>(&want)) {
    const auto& g = std::get<SphereParams>(got);
    EXPECT_EQ(g.center, w->center);
    EXPECT_EQ(g.radius, w->radius);
    EXPECT_EQ(g.pole, w->pole);
    EXPECT_EQ(g.equator, w->equator);
  } else if (const auto* w = std::get_if<CylinderParams>(&want)) {
    const auto& g = std::get<CylinderParams>(got);
    EXPECT_EQ(g.base, w->base);
    EXPECT_EQ(g.axis, w->axis);
    EXPECT_EQ(g.equator, w->equator);
    EXPECT_EQ(g.radius, w->radius);
    EXPECT_EQ(g.height, w->height);
  } else if (const auto* w = std::get_if<ConeParams>(&want)) {
    const auto& g = std::get<ConeParams>(got);
    EXPECT_EQ(g.apex, w->apex);
    EXPECT_EQ(g.axis, w->axis);
    EXPECT_EQ(g.equator, w->equator);
    EXPECT_EQ(g.height, w->height);
    EXPECT_EQ(g.radius, w->radius);
  } else if (const auto* w = std::get_if<DiskParams>(&want)) {
    const auto& g = std::get<DiskParams>(got);
    EXPECT_EQ(g.center, w->center);
    EXPECT_EQ(g.normal, w->normal);
    EXPECT_EQ(g.equator, w->equator);
    EXPECT_EQ(g.radius, w->radius);
  } else if (const auto* w = std::get_if<QuadParams>(&want)) {
    EXPECT_EQ(std::get<QuadParams>(got).corners, w->corners);
  } else {
    const auto& w_plane = std::get<PlaneParams>(want);
    const auto& g = std::get<PlaneParams>(got);
    EXPECT_EQ(g.origin, w_plane.origin);
    EXPECT_EQ(g.u_axis, w_plane.u_axis);
    EXPECT_EQ(g.v_axis, w_plane.v_axis);
  }
}

}  // namespace texbake::testing_params
