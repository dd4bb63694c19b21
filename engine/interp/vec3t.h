// A 3-vector over any scalar-like T: double, interval, jet<double>, jet<interval>.
// Plain aggregate: vec3t<T>{x, y, z}; components default to T{}.
#pragma once

#include <cmath>
#include <concepts>
#include <type_traits>

namespace epsray {

template <class T>
struct vec3t {
  T x{}, y{}, z{};

  constexpr T& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr const T& operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};

namespace vec3t_detail {
template <class S>
struct is_vec3t : std::false_type {};
template <class T>
struct is_vec3t<vec3t<T>> : std::true_type {};
// x^2: sqr (found by ADL) for interval and jet, so that a component containing 0 squares to a
// range >= 0 instead of x * x's [-a, b].
template <class T>
inline T square(const T& x) {
  if constexpr (std::is_arithmetic_v<T>)
    return x * x;
  else
    return sqr(x);
}
}  // namespace vec3t_detail

// A scalar usable with vec3t<T>: anything but a vector whose product with T is a T
// (T itself, double, and interval for jet<interval>).
template <class S, class T>
concept vec3t_scalar = !vec3t_detail::is_vec3t<S>::value && requires(const T& t, const S& s) {
  { t * s } -> std::convertible_to<T>;
  { s * t } -> std::convertible_to<T>;
  { t / s } -> std::convertible_to<T>;
};

template <class T>
inline vec3t<T> operator+(const vec3t<T>& a, const vec3t<T>& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class T>
inline vec3t<T> operator-(const vec3t<T>& a, const vec3t<T>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class T>
inline vec3t<T> operator-(const vec3t<T>& a) {
  return {-a.x, -a.y, -a.z};
}
template <class T, class S>
  requires vec3t_scalar<S, T>
inline vec3t<T> operator*(const vec3t<T>& a, const S& s) {
  return {a.x * s, a.y * s, a.z * s};
}
template <class T, class S>
  requires vec3t_scalar<S, T>
inline vec3t<T> operator*(const S& s, const vec3t<T>& a) {
  return {s * a.x, s * a.y, s * a.z};
}
template <class T, class S>
  requires vec3t_scalar<S, T>
inline vec3t<T> operator/(const vec3t<T>& a, const S& s) {
  return {a.x / s, a.y / s, a.z / s};
}
template <class T>
inline vec3t<T>& operator+=(vec3t<T>& a, const vec3t<T>& b) {
  return a = a + b;
}
template <class T>
inline vec3t<T>& operator-=(vec3t<T>& a, const vec3t<T>& b) {
  return a = a - b;
}

template <class T>
inline T dot(const vec3t<T>& a, const vec3t<T>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
inline vec3t<T> cross(const vec3t<T>& a, const vec3t<T>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
// dot(a, a), computed with squares (the same value for points, tighter for intervals).
template <class T>
inline T length_squared(const vec3t<T>& a) {
  using vec3t_detail::square;
  return square(a.x) + square(a.y) + square(a.z);
}
template <class T>
inline T length(const vec3t<T>& a) {
  using std::sqrt;  // T = double; interval and jet overloads come by ADL
  return sqrt(length_squared(a));
}
// v / sqrt(dot(v, v)). For intervals each component is divided by the enclosure of |v|.
template <class T>
inline vec3t<T> normalize(const vec3t<T>& a) {
  using std::sqrt;
  return a / sqrt(length_squared(a));
}

}  // namespace epsray
