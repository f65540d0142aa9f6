// Small value types for texbake's math: 3D and 2D vectors (double), texture
// coordinates and continuous pixel positions. Standard C++ only.
#pragma once

#include <cmath>

namespace texbake {

// A point or direction in world space. Double precision: the mapping round
// trips are checked to 1e-9.
struct Vec3 {
  double x = 0, y = 0, z = 0;

  constexpr Vec3 operator+(Vec3 o) const { return {x + o.x, y + o.y, z + o.z}; }
  constexpr Vec3 operator-(Vec3 o) const { return {x - o.x, y - o.y, z - o.z}; }
  constexpr Vec3 operator-() const { return {-x, -y, -z}; }
  constexpr Vec3 operator*(double s) const { return {x * s, y * s, z * s}; }
  constexpr Vec3 operator/(double s) const { return {x / s, y / s, z / s}; }
  constexpr Vec3& operator+=(Vec3 o) {
    x += o.x;
    y += o.y;
    z += o.z;
    return *this;
  }
  constexpr Vec3& operator-=(Vec3 o) {
    x -= o.x;
    y -= o.y;
    z -= o.z;
    return *this;
  }
  constexpr Vec3& operator*=(double s) {
    x *= s;
    y *= s;
    z *= s;
    return *this;
  }
  constexpr bool operator==(const Vec3&) const = default;
  constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};

constexpr Vec3 operator*(double s, Vec3 v) {
  return v * s;
}
constexpr double dot(Vec3 a, Vec3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
constexpr Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(Vec3 v) {
  return std::sqrt(dot(v, v));
}
// Precondition: v is not the zero vector (callers validate user vectors first).
inline Vec3 normalize(Vec3 v) {
  return v / length(v);
}
inline bool is_finite(Vec3 v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Texture coordinates, SPEC section 1: (0,0) bottom-left of the image,
// (1,1) top-right.
struct UV {
  double u = 0, v = 0;
  constexpr bool operator==(const UV&) const = default;
};

// A point or direction in a plane (chart coordinates, pixel positions).
struct Vec2 {
  double x = 0, y = 0;

  constexpr Vec2 operator+(Vec2 o) const { return {x + o.x, y + o.y}; }
  constexpr Vec2 operator-(Vec2 o) const { return {x - o.x, y - o.y}; }
  constexpr Vec2 operator*(double s) const { return {x * s, y * s}; }
  constexpr bool operator==(const Vec2&) const = default;
};

constexpr double dot(Vec2 a, Vec2 b) {
  return a.x * b.x + a.y * b.y;
}
// The z component of (a, 0) x (b, 0): twice the signed area of (0, a, b).
constexpr double cross(Vec2 a, Vec2 b) {
  return a.x * b.y - a.y * b.x;
}

// Continuous pixel position: texel centres at integers, x to the right,
// y down from the top row (the image's storage order).
using PixelPos = Vec2;

}  // namespace texbake
