#include "segments.h"

#include <algorithm>
#include <cmath>

namespace epsray {

namespace {

double degrees_between(const vec3& a, const vec3& b) {
  const double d = std::clamp(double(glm::dot(a, b)), -1.0, 1.0);
  return std::acos(d) * 180.0 / 3.14159265358979323846;
}

// The median of the values that are not zero (0 when all are): a path's typical step
// while it moves, whatever its pauses.
double median_moving(std::vector<double> v) {
  v.erase(std::remove(v.begin(), v.end(), 0.0), v.end());
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
  return v[v.size() / 2];
}

bool starts_block(int k, int keyframe) { return keyframe <= 0 || k % keyframe == 0; }

// Segment costs in O(1) from prefix sums of the warm costs.
struct cost_table {
  const frame_costs& c;
  std::vector<double> warm_sum;  // warm_sum[k]: warm costs of frames 0..k-1
  explicit cost_table(const frame_costs& fc) : c(fc), warm_sum(fc.warm.size() + 1, 0.0) {
    for (size_t k = 0; k < fc.warm.size(); ++k) warm_sum[k + 1] = warm_sum[k] + fc.warm[k];
  }
  double operator()(int first, int last) const {
    return first > last ? 0.0 : c.cold[size_t(first)] + warm_sum[size_t(last) + 1] - warm_sum[size_t(first) + 1];
  }
};

// Greedy: each segment takes as many whole blocks as keep its cost within `bound`. Fewest
// segments for that bound (a later start never makes the rest dearer). Empty when a
// single block is over the bound.
std::vector<segment> fill_greedily(const cost_table& cost, const std::vector<int>& block_starts, int frames,
                                   double bound) {
  std::vector<segment> out;
  const size_t blocks = block_starts.size();
  auto block_end = [&](size_t b) { return b + 1 < blocks ? block_starts[b + 1] - 1 : frames - 1; };
  for (size_t i = 0; i < blocks;) {
    size_t j = i;
    if (cost(block_starts[i], block_end(i)) > bound) return {};
    while (j + 1 < blocks && cost(block_starts[i], block_end(j + 1)) <= bound) ++j;
    out.push_back({block_starts[i], block_end(j)});
    i = j + 1;
  }
  return out;
}

}  // namespace

frame_costs estimate_frame_costs(const std::vector<camera_view>& frames, int keyframe, const frame_cost_model& m) {
  const size_t n = frames.size();
  std::vector<double> steps(n, 0.0), turns(n, 0.0);
  std::vector<vec3> forward(n), right(n);
  for (size_t k = 0; k < n; ++k) {
    const camera_view& v = frames[k];
    vec3 f = v.at - v.from, r = glm::cross(f, v.up);
    forward[k] = glm::length(f) > 0 ? glm::normalize(f) : (k ? forward[k - 1] : vec3(0, 0, -1));
    right[k] = glm::length(r) > 0 ? glm::normalize(r) : (k ? right[k - 1] : vec3(1, 0, 0));
    if (k == 0) continue;
    steps[k] = glm::length(v.from - frames[k - 1].from);
    // Yaw and pitch move the forward axis, a roll the right one; a zoom changes the angle.
    turns[k] = std::max(degrees_between(forward[k], forward[k - 1]), degrees_between(right[k], right[k - 1])) +
               std::abs(double(v.angle) - double(frames[k - 1].angle));
  }
  const double step = median_moving(steps), turn = median_moving(turns);
  frame_costs c{std::vector<double>(n, m.cold), std::vector<double>(n, 0.0), std::vector<bool>(n, false)};
  for (size_t k = 0; k < n; ++k) {
    c.teleport[k] = k > 0 && ((step > 0 && steps[k] > m.teleport_steps * step) || turns[k] > m.teleport_degrees);
    const double motion = (step > 0 ? steps[k] / step : 0.0) + (turn > 0 ? turns[k] / turn : 0.0);
    c.warm[k] = 1.0 + m.per_motion * std::min(m.max_motion, motion);
    if (k == 0 || c.teleport[k] || (keyframe > 0 && int(k) % keyframe == 0)) c.warm[k] = m.cold;
  }
  return c;
}

double segment_cost(const frame_costs& c, int first, int last) { return cost_table(c)(first, last); }

std::vector<segment> split_path(const frame_costs& c, int parts, int keyframe) {
  const int frames = int(c.warm.size());
  std::vector<int> block_starts;
  for (int k = 0; k < frames; ++k)
    if (starts_block(k, keyframe)) block_starts.push_back(k);
  const cost_table cost(c);
  std::vector<segment> segs;
  if (frames > 0 && parts > 0) {
    // The smallest bound the greedy fill meets with `parts` segments, by bisection.
    double lo = 0, hi = cost(0, frames - 1);
    for (int it = 0; it < 200 && hi - lo > 1e-12 * hi; ++it) {
      const double mid = 0.5 * (lo + hi);
      const std::vector<segment> s = fill_greedily(cost, block_starts, frames, mid);
      (!s.empty() && int(s.size()) <= parts ? hi : lo) = mid;
    }
    segs = fill_greedily(cost, block_starts, frames, hi);
    // Fewer segments than parts: split the dearest at its best block boundary (a split
    // never raises the largest cost), while one has two blocks.
    while (int(segs.size()) < parts) {
      int best = -1, cut = -1;
      double best_cost = -1;
      for (int i = 0; i < int(segs.size()); ++i) {
        const segment& s = segs[size_t(i)];
        const double here = cost(s.first, s.last);
        if (here <= best_cost) continue;
        int at = -1;
        double split = 0;
        for (int b : block_starts)
          if (b > s.first && b <= s.last) {
            const double worse = std::max(cost(s.first, b - 1), cost(b, s.last));
            if (at < 0 || worse < split) at = b, split = worse;
          }
        if (at >= 0) best = i, cut = at, best_cost = here;
      }
      if (best < 0) break;
      const segment s = segs[size_t(best)];
      segs[size_t(best)] = {s.first, cut - 1};
      segs.insert(segs.begin() + best + 1, segment{cut, s.last});
    }
    // A boundary moved onto the nearest teleport within its two segments, where neither
    // then costs more than the largest: the teleport is paid cold once instead of twice.
    double largest = 0;
    for (const segment& s : segs) largest = std::max(largest, cost(s.first, s.last));
    const double bound = largest * (1 + 1e-12);
    for (size_t i = 1; i < segs.size(); ++i) {
      const int start = segs[i].first;
      if (c.teleport[size_t(start)]) continue;
      int pick = -1;
      for (int t = segs[i - 1].first + 1; t <= segs[i].last; ++t) {
        if (!c.teleport[size_t(t)] || !starts_block(t, keyframe)) continue;
        if (cost(segs[i - 1].first, t - 1) > bound || cost(t, segs[i].last) > bound) continue;
        if (pick < 0 || std::abs(t - start) < std::abs(pick - start)) pick = t;
      }
      if (pick >= 0) segs[i - 1].last = pick - 1, segs[i].first = pick;
    }
  }
  while (int(segs.size()) < parts) segs.push_back({frames, frames - 1});
  return segs;
}

}  // namespace epsray
