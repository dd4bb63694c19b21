// segments: how a walk's path is split over mpirun's ranks (cli/segments.h), without MPI:
// contiguous segments covering every frame once, balanced by the estimated cost (as good
// as the best split found by trying every one), starting at keyframes when asked, and at a
// teleport where that costs nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <random>

#include "segments.h"

namespace epsray {
namespace {

// A walk along x, one unit a frame, looking ahead; `jumps` frames move 50 units instead.
std::vector<camera_view> walk_along_x(int frames, std::vector<int> jumps = {}) {
  std::vector<camera_view> path;
  float x = 0;
  for (int k = 0; k < frames; ++k) {
    if (k > 0) x += std::find(jumps.begin(), jumps.end(), k) != jumps.end() ? 50.f : 1.f;
    camera_view v;
    v.from = {x, 0, 0}, v.at = {x + 1, 0, 0}, v.up = {0, 0, 1};
    path.push_back(v);
  }
  return path;
}

void expect_cover(const std::vector<segment>& segs, int frames, int parts) {
  ASSERT_EQ(int(segs.size()), parts);
  int next = 0;
  for (const segment& s : segs) {
    if (s.frames() <= 0) {
      EXPECT_EQ(s.first, frames) << "empty segments come last";
      continue;
    }
    EXPECT_EQ(s.first, next) << "contiguous, in order";
    next = s.last + 1;
  }
  EXPECT_EQ(next, frames) << "every frame once";
}

double largest_cost(const frame_costs& c, const std::vector<segment>& segs) {
  double m = 0;
  for (const segment& s : segs)
    if (s.frames() > 0) m = std::max(m, segment_cost(c, s.first, s.last));
  return m;
}

// The smallest largest cost over every split of frames 0..n-1 into at most `parts`
// segments starting where `may_start` allows.
double best_by_trying_all(const frame_costs& c, int parts, const std::function<bool(int)>& may_start) {
  const int n = int(c.warm.size());
  double best = 1e300;
  std::function<void(int, int, double)> go = [&](int first, int left, double worst) {
    if (first == n) return void(best = std::min(best, worst));
    if (left == 0) return;
    for (int last = first; last < n; ++last)
      if (last + 1 == n || may_start(last + 1)) go(last + 1, left - 1, std::max(worst, segment_cost(c, first, last)));
  };
  go(0, parts, 0);
  return best;
}

TEST(Segments, EvenWalkSplitsIntoEqualShares) {
  const frame_costs c = estimate_frame_costs(walk_along_x(60), 0);
  EXPECT_DOUBLE_EQ(c.cold[0], frame_cost_model{}.cold);
  EXPECT_DOUBLE_EQ(c.warm[0], frame_cost_model{}.cold) << "the first frame is always cold";
  EXPECT_DOUBLE_EQ(c.warm[1], 1.2) << "one median step: 1 + 0.2";
  for (int parts : {1, 2, 3, 4, 7}) {
    const std::vector<segment> segs = split_path(c, parts, 0);
    expect_cover(segs, 60, parts);
    // Within a cold start of an equal share (the greedy fill leaves the slack to the last).
    for (const segment& s : segs) EXPECT_NEAR(s.frames(), 60.0 / parts, 3.0) << parts << " parts";
  }
}

TEST(Segments, StaticFramesCostLessThanMovingOnes) {
  std::vector<camera_view> path = walk_along_x(10);
  path.insert(path.end(), 10, path.back());  // stands still for ten frames
  const frame_costs c = estimate_frame_costs(path, 0);
  EXPECT_DOUBLE_EQ(c.warm[15], 1.0);
  EXPECT_GT(c.warm[5], c.warm[15]);
  const std::vector<segment> segs = split_path(c, 2, 0);
  expect_cover(segs, 20, 2);
  EXPECT_GT(segs[1].frames(), segs[0].frames()) << "the still half is cheaper per frame";
}

TEST(Segments, TeleportIsFoundAndStartsASegment) {
  const frame_costs c = estimate_frame_costs(walk_along_x(60, {31}), 0);
  for (int k = 0; k < 60; ++k) EXPECT_EQ(c.teleport[size_t(k)], k == 31) << k;
  EXPECT_DOUBLE_EQ(c.warm[31], c.cold[31]) << "a teleport is paid cold in any segment";
  const std::vector<segment> segs = split_path(c, 2, 0);
  expect_cover(segs, 60, 2);
  EXPECT_EQ(segs[1].first, 31);
}

TEST(Segments, TeleportNearTheBalancedBoundaryIsSnappedTo) {
  // 30 frames over 3 ranks: the greedy fill ends the second segment at 19, the teleport;
  // the third segment has room, so the boundary moves back onto the teleport, which is
  // then paid cold once, as the segment's start.
  const frame_costs c = estimate_frame_costs(walk_along_x(30, {19}), 0);
  const std::vector<segment> segs = split_path(c, 3, 0);
  expect_cover(segs, 30, 3);
  EXPECT_EQ(segs[2].first, 19);
  EXPECT_NEAR(largest_cost(c, segs), best_by_trying_all(c, 3, [](int) { return true; }), 1e-9);
}

TEST(Segments, LargeTurnIsATeleport) {
  std::vector<camera_view> path = walk_along_x(20);
  for (int k = 10; k < 20; ++k) path[size_t(k)].at = path[size_t(k)].from + vec3(0, 1, 0);  // a 90 degree turn at 10
  const frame_costs c = estimate_frame_costs(path, 0);
  EXPECT_TRUE(c.teleport[10]);
  EXPECT_FALSE(c.teleport[11]);
}

TEST(Segments, KeyframesAreTheOnlyStarts) {
  const frame_costs c = estimate_frame_costs(walk_along_x(95), 10);
  for (int k = 0; k < 95; ++k) EXPECT_EQ(c.warm[size_t(k)] == c.cold[size_t(k)], k % 10 == 0) << k;
  for (int parts : {2, 3, 4, 9, 10, 12}) {
    const std::vector<segment> segs = split_path(c, parts, 10);
    expect_cover(segs, 95, parts);
    for (const segment& s : segs)
      if (s.frames() > 0) {
        EXPECT_EQ(s.first % 10, 0) << parts << " parts";
      }
    EXPECT_NEAR(largest_cost(c, segs), best_by_trying_all(c, std::min(parts, 10), [](int k) { return k % 10 == 0; }),
                1e-9)
        << parts << " parts";
  }
}

TEST(Segments, MoreRanksThanFramesLeavesTheLastOnesEmpty) {
  const frame_costs c = estimate_frame_costs(walk_along_x(3), 0);
  const std::vector<segment> segs = split_path(c, 5, 0);
  expect_cover(segs, 3, 5);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(segs[size_t(i)].frames(), 1);
  EXPECT_EQ(segs[3].frames(), 0);
  expect_cover(split_path(estimate_frame_costs({}, 0), 4, 0), 0, 4);
}

TEST(Segments, AsGoodAsTryingEverySplit) {
  std::mt19937 g(7);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + int(g() % 12), parts = 1 + int(g() % 4);
    std::vector<camera_view> path;
    vec3 at(0);
    for (int k = 0; k < n; ++k) {
      at += vec3(float(g() % 5), float(g() % 3), 0);  // steps of 0 to ~5, now and then a jump
      if (g() % 7 == 0) at += vec3(100, 0, 0);
      camera_view v;
      v.from = at, v.at = at + vec3(1, float(g() % 3) * 0.1f, 0), v.up = {0, 0, 1};
      path.push_back(v);
    }
    const int keyframe = trial % 3 == 0 ? 3 : 0;
    const frame_costs c = estimate_frame_costs(path, keyframe);
    const std::vector<segment> segs = split_path(c, parts, keyframe);
    expect_cover(segs, n, parts);
    const double best = best_by_trying_all(c, parts, [&](int k) { return keyframe == 0 || k % keyframe == 0; });
    EXPECT_NEAR(largest_cost(c, segs), best, 1e-9 * best) << "trial " << trial;
  }
}

}  // namespace
}  // namespace epsray
