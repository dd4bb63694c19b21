#include "predicate/shaft.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

namespace epsray {

namespace {

bool is_empty(const bounds& b) { return b.lo.x > b.hi.x || b.lo.y > b.hi.y || b.lo.z > b.hi.z; }

// Smallest float >= x (x finite, |x| < FLT_MAX), without branches: whether float(x) fell
// below x is a coin toss, and mispredicted branches there cost more than all the rest.
float round_up(double x) {
  float f = float(x) + 0.0f;  // -0 -> +0, so that stepping up from 0 gives +denorm_min
  std::int32_t bits = std::bit_cast<std::int32_t>(f), below = double(f) < x, sign = bits >> 31;
  return std::bit_cast<float>(bits + ((below ^ sign) - sign));  // +below, or -below if f < 0
}

// One of the 12 edge directions of a box: axes i < j, and the signs of the faces there.
struct edge_dir {
  int i, j, si, sj;
};
constexpr edge_dir edge_dirs[12] = {
    {0, 1, -1, -1}, {0, 1, -1, 1}, {0, 1, 1, -1}, {0, 1, 1, 1},  //
    {0, 2, -1, -1}, {0, 2, -1, 1}, {0, 2, 1, -1}, {0, 2, 1, 1},  //
    {1, 2, -1, -1}, {1, 2, -1, 1}, {1, 2, 1, -1}, {1, 2, 1, 1}};

// Planes collected without branching: slot 8 takes the edges that get none.
struct plane_set {
  float n[3][shaft_max_planes + 1] = {};
  float d[shaft_max_planes + 1];
  int k = 0;
};

// The plane, if any, through the E-edges of A and B. face[box][f] holds the coordinate of
// face direction f = 2 * axis + (sign > 0) of A (box 0) or B (box 1); who[f] is +1 when A
// reaches farther along f, -1 when B does, 0 on a tie.
template <edge_dir E>
inline void edge_plane(const float (&face)[2][6], const int (&who)[6], double pad, plane_set& out) {
  constexpr int fi = 2 * E.i + (E.si > 0), fj = 2 * E.j + (E.sj > 0);
  const int wi = who[fi], wj = who[fj];
  // A plane joins the edges when one box reaches farther along d1 = (i, si) and the other
  // along d2 = (j, sj). P is the one farther along d1, Q the one farther along d2.
  const int p = wi < 0, q = 1 - p;
  const float pu = face[p][fi], pv = face[p][fj], qu = face[q][fi], qv = face[q][fj];
  // In outward coordinates (si x_i, sj x_j) P's edge is farther along the first and Q's
  // along the second, so the outward normal there is (sj (qv - pv), si (pu - qu)), i.e.
  // n_i = si sj (qv - pv), n_j = si sj (pu - qu): of sign si and sj. Float differences
  // keep their sign, and any normal with those signs (third component 0) finds both boxes'
  // largest n . x on these edges, so the offset below (exact products in double, the
  // larger of the two edges) gives a half-space holding A and B whole.
  constexpr float sg = float(E.si * E.sj);
  const float ni = sg * (qv - pv), nj = sg * (pu - qu);
  double off = std::max(double(ni) * pu + double(nj) * pv, double(ni) * qu + double(nj) * qv);
  // Pushed out by the slack: pad * (|ni| + |nj|) is at least pad times the normal's length.
  off += pad * (double(std::fabs(ni)) + double(std::fabs(nj)));
  // At most 8 edges are mixed (3 + 3 directions less one same-axis pair, or 4 + 2); the
  // k < 8 test only keeps a miscount from overflowing (a dropped plane keeps more boxes).
  const int keep = (wi * wj < 0) & (out.k < shaft_max_planes);
  const int slot = shaft_max_planes + keep * (out.k - shaft_max_planes);
  out.n[E.i][slot] = ni, out.n[E.j][slot] = nj, out.d[slot] = round_up(off);
  out.k += keep;
}

}  // namespace

shaft make_shaft(const bounds& a, const bounds& b) {
  shaft s;  // empty, no planes
  const bool ea = is_empty(a), eb = is_empty(b);
  if (ea && eb) return s;  // default bounds: empty, culls every finite box
  bounds u = ea ? b : a;
  if (!ea && !eb) u.grow(b);

  // Slack relative to the largest coordinate (float error scales with it); never zero.
  const float ulo[3] = {u.lo.x, u.lo.y, u.lo.z}, uhi[3] = {u.hi.x, u.hi.y, u.hi.z};
  float scale = 0;
  for (int i = 0; i < 3; ++i) scale = std::max(scale, std::max(std::fabs(ulo[i]), std::fabs(uhi[i])));
  const double pad = std::max(double(shaft_rel_tol) * double(scale), double(std::numeric_limits<float>::min()));
  float blo[3], bhi[3];
  for (int i = 0; i < 3; ++i) blo[i] = -round_up(-(double(ulo[i]) - pad)), bhi[i] = round_up(double(uhi[i]) + pad);
  s.box = bounds{vec3(blo[0], blo[1], blo[2]), vec3(bhi[0], bhi[1], bhi[2])};
  if (ea || eb) return s;  // one box alone: its hull is its box

  // Plain arrays: glm's vec3::operator[] is a switch, whose branches cost more than the
  // arithmetic here.
  const float face[2][6] = {{a.lo.x, a.hi.x, a.lo.y, a.hi.y, a.lo.z, a.hi.z},
                            {b.lo.x, b.hi.x, b.lo.y, b.hi.y, b.lo.z, b.hi.z}};
  int who[6];
  for (int f = 0; f < 6; ++f) {
    float fa = f & 1 ? face[0][f] : -face[0][f], fb = f & 1 ? face[1][f] : -face[1][f];
    who[f] = (fa > fb) - (fb > fa);
  }
  plane_set ps;
  for (float& d : ps.d) d = std::numeric_limits<float>::infinity();
  [&]<std::size_t... e>(std::index_sequence<e...>) {
    (edge_plane<edge_dirs[e]>(face, who, pad, ps), ...);
  }(std::make_index_sequence<12>{});
  for (int j = 0; j < shaft_max_planes; ++j)
    s.nx[j] = ps.n[0][j], s.ny[j] = ps.n[1][j], s.nz[j] = ps.n[2][j], s.d[j] = ps.d[j];
  s.planes = ps.k;
  return s;
}

}  // namespace epsray
