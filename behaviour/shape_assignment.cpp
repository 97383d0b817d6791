// The assignment of robots to the shape's places (shape_assignment.hpp says what and why).
#include "behaviour/shape_assignment.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace swarmform::shape_metrics {

namespace {

constexpr int kMaxRounds = 20;  // fit <-> assignment alternations; each lowers the cost, so few are needed
constexpr std::size_t kMaxFullRounds = 4;  // Hungarian solves per refinement; after them, an upper bound
constexpr int kGreedyRounds = 8;           // cheap nearest-place rounds per starting angle of the fallback
constexpr double kRetryAbove = 0.1;  // grid units: a worse result is also tried from the shape's heading

double squared(Vec2 a, Vec2 b) {
  const double dx = a.x - b.x;
  const double dy = a.y - b.y;
  return dx * dx + dy * dy;
}

// The points' centroid ((0, 0) for none).
Vec2 centroid(const std::vector<Vec2>& points) {
  Vec2 m;
  for (const Vec2& p : points) {
    m.x += p.x;
    m.y += p.y;
  }
  const double n = static_cast<double>(std::max<std::size_t>(points.size(), 1));
  return {m.x / n, m.y / n};
}

// Each point's distance from the points' centroid, ascending.
std::vector<double> radii_from_centroid(const std::vector<Vec2>& points) {
  const Vec2 m = centroid(points);
  std::vector<double> out;
  out.reserve(points.size());
  for (const Vec2& p : points) out.push_back(std::sqrt(squared(p, m)));
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

Vec2 RigidFit::apply(Vec2 p) const {
  const double c = std::cos(angle);
  const double s = std::sin(angle);
  return {c * p.x - s * p.y + translation.x, s * p.x + c * p.y + translation.y};
}

Vec2 RigidFit::invert(Vec2 q) const {
  const double c = std::cos(angle);
  const double s = std::sin(angle);
  const double x = q.x - translation.x;
  const double y = q.y - translation.y;
  return {c * x + s * y, -s * x + c * y};
}

ShapeAssigner::ShapeAssigner(const ShapeMatrix& shape, double grid_spacing, double heading)
    : shape_(shape), spacing_(grid_spacing), heading_(heading) {
  places_.resize(static_cast<std::size_t>(std::max(shape.label_count(), 0)));
  for (int row = 0; row < shape.rows; ++row) {
    for (int col = 0; col < shape.cols; ++col) {
      const int label = shape.at(row, col);
      if (label >= 0 && static_cast<std::size_t>(label) < places_.size()) {
        places_[static_cast<std::size_t>(label)] = {col * grid_spacing, -row * grid_spacing};
      }
    }
  }
  place_radii_ = radii_from_centroid(places_);
}

double ShapeAssigner::error_lower_bound(const std::vector<Vec2>& robots) const {
  // With every robot at a place, the best fit puts the places' centroid on the robots' (Kabsch), so with a
  // robot's and its place's offsets a and b from their centroids the cost is the sum of |a - R b|^2 >=
  // (|a| - |b|)^2 (the triangle inequality), whatever the rotation R; and of every pairing of the two sets
  // of radii the sorted one has the least sum of squared differences (the rearrangement inequality).
  const std::size_t n = robots.size();
  if (n == 0 || n != places_.size() || spacing_ <= 0.0) return 0.0;
  const std::vector<double> radii = radii_from_centroid(robots);
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) sum += (radii[i] - place_radii_[i]) * (radii[i] - place_radii_[i]);
  return std::sqrt(sum / static_cast<double>(n)) / spacing_;
}

std::vector<int> ShapeAssigner::clean_guess(const std::vector<int>& guess) const {
  std::vector<int> out(guess.size(), -1);
  std::vector<char> taken(places_.size(), 0);
  for (std::size_t i = 0; i < guess.size(); ++i) {
    const int l = guess[i];
    if (l < 0 || static_cast<std::size_t>(l) >= places_.size() || taken[static_cast<std::size_t>(l)])
      continue;
    taken[static_cast<std::size_t>(l)] = 1;
    out[i] = l;
  }
  return out;
}

// 2-D Kabsch on the labelled pairs: theta = atan2(sum p x q, sum p . q) on centred points (proper rotations
// only). Under 2 pairs: the shape turned to the heading, its centre (or its one pair) on the robots'.
RigidFit ShapeAssigner::fit_pairs(const std::vector<Vec2>& robots, const std::vector<int>& labels) const {
  Vec2 pm;
  Vec2 qm;
  std::size_t n = 0;
  for (std::size_t i = 0; i < robots.size(); ++i) {
    if (labels[i] < 0) continue;
    const Vec2 p = places_[static_cast<std::size_t>(labels[i])];
    pm.x += p.x;
    pm.y += p.y;
    qm.x += robots[i].x;
    qm.y += robots[i].y;
    ++n;
  }
  RigidFit fit;
  if (n < 2) {
    fit.angle = heading_ - std::numbers::pi / 2.0;
    if (n == 0) {  // centre on centre
      pm = centroid(places_);
      qm = centroid(robots);
    }
    const Vec2 rp = RigidFit{fit.angle, {}}.apply(pm);
    fit.translation = {qm.x - rp.x, qm.y - rp.y};
    return fit;
  }
  const double dn = static_cast<double>(n);
  pm = {pm.x / dn, pm.y / dn};
  qm = {qm.x / dn, qm.y / dn};
  double s_dot = 0.0;
  double s_cross = 0.0;
  for (std::size_t i = 0; i < robots.size(); ++i) {
    if (labels[i] < 0) continue;
    const Vec2 p = places_[static_cast<std::size_t>(labels[i])];
    const double px = p.x - pm.x, py = p.y - pm.y;
    const double qx = robots[i].x - qm.x, qy = robots[i].y - qm.y;
    s_dot += px * qx + py * qy;
    s_cross += px * qy - py * qx;
  }
  fit.angle = std::atan2(s_cross, s_dot);
  const Vec2 rp = RigidFit{fit.angle, {}}.apply(pm);
  fit.translation = {qm.x - rp.x, qm.y - rp.y};
  return fit;
}

std::pair<int, double> ShapeAssigner::nearest_place(Vec2 point, const RigidFit& fit) const {
  const Vec2 u = fit.invert(point);
  const double col = std::round(u.x / spacing_);
  const double row = std::round(-u.y / spacing_);
  if (!(col >= 0 && row >= 0 && col < shape_.cols && row < shape_.rows)) return {-1, 0.0};
  const int label = shape_.at(static_cast<int>(row), static_cast<int>(col));
  if (label < 0) return {-1, 0.0};
  return {label, std::sqrt(squared(u, places_[static_cast<std::size_t>(label)]))};
}

bool ShapeAssigner::certified_assignment(const std::vector<Vec2>& robots, const RigidFit& fit,
                                         std::vector<int>& out) const {
  const std::size_t n = places_.size();
  const std::size_t k = std::min(robots.size(), n);
  std::vector<int> holder(n, -1);
  std::vector<double> holder_cost(n, 0.0);
  std::vector<double> lower(robots.size(), 0.0);  // each robot's least possible cost (squared m)
  const double half = spacing_ / 2.0;
  for (std::size_t i = 0; i < robots.size(); ++i) {
    const Vec2 u = fit.invert(robots[i]);
    const double gx = u.x / spacing_;
    const double gy = -u.y / spacing_;
    if (!std::isfinite(gx) || !std::isfinite(gy)) return false;
    const double col = std::round(gx);
    const double row = std::round(gy);
    int label = -1;
    if (col >= 0 && row >= 0 && col < shape_.cols && row < shape_.rows) {
      label = shape_.at(static_cast<int>(row), static_cast<int>(col));
    }
    if (label >= 0) {
      const double d = squared(u, places_[static_cast<std::size_t>(label)]);
      lower[i] = d;
      const auto l = static_cast<std::size_t>(label);
      if (holder[l] < 0 || d < holder_cost[l]) {
        holder[l] = static_cast<int>(i);
        holder_cost[l] = d;
      }
    } else {
      // No place in this grid cell: every place is at least as far as the cell's edge, and as the grid's
      // bounding box.
      const double edge = std::max(
          0.0, std::min(half - std::abs(u.x - col * spacing_), half - std::abs(-u.y - row * spacing_)));
      const double bx = std::max({0.0, -u.x, u.x - (shape_.cols - 1) * spacing_});
      const double by = std::max({0.0, u.y, -u.y - (shape_.rows - 1) * spacing_});
      const double box = std::hypot(bx, by);
      lower[i] = std::max(edge, box) * std::max(edge, box);
    }
  }
  out.assign(robots.size(), -1);
  std::size_t held = 0;
  double worst_taken = 0.0;
  for (std::size_t l = 0; l < n; ++l) {
    if (holder[l] < 0) continue;
    out[static_cast<std::size_t>(holder[l])] = static_cast<int>(l);
    worst_taken = std::max(worst_taken, holder_cost[l]);
    ++held;
  }
  if (held != k) return false;
  for (std::size_t i = 0; i < robots.size(); ++i) {
    if (out[i] < 0 && lower[i] < worst_taken) return false;
  }
  return true;
}

void ShapeAssigner::hungarian_assignment(const std::vector<Vec2>& robots, const RigidFit& fit,
                                         std::vector<int>& out) const {
  const std::size_t m = robots.size();
  const std::size_t n = places_.size();
  std::vector<Vec2> fitted(n);
  for (std::size_t j = 0; j < n; ++j) fitted[j] = fit.apply(places_[j]);
  out.assign(m, -1);
  if (m == 0 || n == 0) return;
  if (m <= n) {
    std::vector<double> cost(m * n);
    for (std::size_t i = 0; i < m; ++i)
      for (std::size_t j = 0; j < n; ++j) cost[i * n + j] = squared(robots[i], fitted[j]);
    const auto col = hungarian(cost, m, n);
    for (std::size_t i = 0; i < m; ++i) out[i] = col[i];
  } else {
    std::vector<double> cost(n * m);
    for (std::size_t j = 0; j < n; ++j)
      for (std::size_t i = 0; i < m; ++i) cost[j * m + i] = squared(robots[i], fitted[j]);
    const auto col = hungarian(cost, n, m);
    for (std::size_t j = 0; j < n; ++j) out[static_cast<std::size_t>(col[j])] = static_cast<int>(j);
  }
}

ShapeAssignment ShapeAssigner::evaluate(const std::vector<Vec2>& robots,
                                        const std::vector<int>& labels) const {
  ShapeAssignment a;
  a.label = clean_guess(labels);
  a.fit = fit_pairs(robots, a.label);
  double sum = 0.0;
  for (std::size_t i = 0; i < robots.size(); ++i) {
    if (a.label[i] < 0) continue;
    sum += squared(a.fit.apply(places_[static_cast<std::size_t>(a.label[i])]), robots[i]);
    ++a.assigned;
  }
  if (a.assigned > 0 && spacing_ > 0.0) a.error = std::sqrt(sum / static_cast<double>(a.assigned)) / spacing_;
  return a;
}

std::vector<double> ShapeAssigner::candidate_angles(const std::vector<Vec2>& robots) const {
  // The grid's orientation modulo a quarter turn, from the robots' axis neighbours (pairs about one spacing
  // apart; diagonal pairs, 1.41 spacings, are left out): the mean of 4 x their directions.
  double c4 = 0.0;
  double s4 = 0.0;
  std::size_t pairs = 0;
  const double lo = 0.75 * spacing_ * 0.75 * spacing_;
  const double hi = 1.25 * spacing_ * 1.25 * spacing_;
  for (std::size_t i = 0; i < robots.size(); ++i) {
    for (std::size_t j = i + 1; j < robots.size(); ++j) {
      const double d = squared(robots[i], robots[j]);
      if (d < lo || d > hi) continue;
      const double a = 4.0 * std::atan2(robots[j].y - robots[i].y, robots[j].x - robots[i].x);
      c4 += std::cos(a);
      s4 += std::sin(a);
      ++pairs;
    }
  }
  std::vector<double> angles{heading_ - std::numbers::pi / 2.0};
  if (pairs > 0 && std::hypot(c4, s4) > 1e-9) {
    const double base = std::atan2(s4, c4) / 4.0;
    for (int k = 0; k < 4; ++k) angles.push_back(base + k * std::numbers::pi / 2.0);
  } else {
    for (int k = 1; k < 12; ++k) angles.push_back(angles[0] + k * std::numbers::pi / 6.0);
  }
  return angles;
}

ShapeAssignment ShapeAssigner::refine(const std::vector<Vec2>& robots, RigidFit fit, std::vector<int> labels,
                                      bool full_solve) const {
  std::size_t solves = 0;
  bool optimal = false;
  for (int round = 0; round < kMaxRounds; ++round) {
    std::vector<int> next;
    if (certified_assignment(robots, fit, next)) {
      optimal = true;
    } else if (full_solve && solves < kMaxFullRounds) {
      hungarian_assignment(robots, fit, next);
      ++solves;
      optimal = true;
    } else {
      optimal = false;
      break;
    }
    if (next == labels) break;
    labels = std::move(next);
    fit = fit_pairs(robots, labels);
    optimal = false;  // for the previous fit; the next round checks the new one
  }
  ShapeAssignment a = evaluate(robots, labels);
  a.optimal = optimal;
  a.full_solves = solves;
  return a;
}

ShapeAssignment ShapeAssigner::solve(const std::vector<Vec2>& robots, const std::vector<int>& guess,
                                     bool full_solve) const {
  std::vector<int> labels = clean_guess(guess);
  const auto guessed =
      static_cast<std::size_t>(std::count_if(labels.begin(), labels.end(), [](int l) { return l >= 0; }));
  ShapeAssignment best;
  if (guessed >= 2 || !full_solve || robots.size() < 2) {
    best = refine(robots, fit_pairs(robots, labels), labels, full_solve);
    if (!full_solve || best.error <= kRetryAbove || robots.size() < 2) return best;
  }
  // The guess led nowhere good: start again from the shape laid on the robots' centre at each of a few
  // angles (the grid's own orientation, read from the robots, and its quarter turns; the heading).
  std::size_t solves = best.full_solves;
  // Translation: the robots' centre onto the places' centre.
  const Vec2 pm = centroid(places_);
  const Vec2 qm = centroid(robots);
  // Each start is first improved cheaply (every robot to its nearest place, the nearest robot winning a
  // place wanted twice, then a refit; no Hungarian solve); only the best is refined in full.
  ShapeAssignment start_best;
  for (const double angle : candidate_angles(robots)) {
    RigidFit fit{angle, {}};
    const Vec2 rp = fit.apply(pm);
    fit.translation = {qm.x - rp.x, qm.y - rp.y};
    std::vector<int> greedy(robots.size(), -1);
    for (int round = 0; round < kGreedyRounds; ++round) {
      std::vector<int> next;
      certified_assignment(robots, fit, next);
      if (next == greedy) break;
      greedy = std::move(next);
      fit = fit_pairs(robots, greedy);
    }
    ShapeAssignment scored = evaluate(robots, greedy);
    if (scored.assigned > start_best.assigned ||
        (scored.assigned == start_best.assigned && scored.error < start_best.error)) {
      start_best = std::move(scored);
    }
  }
  ShapeAssignment other = refine(robots, start_best.fit, start_best.label, true);
  solves += other.full_solves;
  if (other.assigned >= best.assigned && other.error < best.error) best = std::move(other);
  best.full_solves = solves;
  return best;
}

std::vector<int> hungarian(const std::vector<double>& cost, std::size_t rows, std::size_t cols) {
  // The shortest augmenting path form with potentials (Kuhn-Munkres; Jonker-Volgenant's Dijkstra step), on
  // 1-based arrays where column 0 is the virtual start.
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(rows + 1, 0.0);
  std::vector<double> v(cols + 1, 0.0);
  std::vector<std::size_t> p(cols + 1, 0);
  std::vector<std::size_t> way(cols + 1, 0);
  std::vector<double> minv(cols + 1);
  std::vector<char> used(cols + 1);
  for (std::size_t i = 1; i <= rows; ++i) {
    p[0] = i;
    std::size_t j0 = 0;
    std::fill(minv.begin(), minv.end(), inf);
    std::fill(used.begin(), used.end(), 0);
    do {
      used[j0] = 1;
      const std::size_t i0 = p[j0];
      double delta = inf;
      std::size_t j1 = 0;
      const double* row = &cost[(i0 - 1) * cols];
      for (std::size_t j = 1; j <= cols; ++j) {
        if (used[j]) continue;
        const double cur = row[j - 1] - u[i0] - v[j];
        if (cur < minv[j]) {
          minv[j] = cur;
          way[j] = j0;
        }
        if (minv[j] < delta) {
          delta = minv[j];
          j1 = j;
        }
      }
      if (j1 == 0) break;  // only with non-finite costs: leave the row unassigned
      for (std::size_t j = 0; j <= cols; ++j) {
        if (used[j]) {
          u[p[j]] += delta;
          v[j] -= delta;
        } else {
          minv[j] -= delta;
        }
      }
      j0 = j1;
    } while (p[j0] != 0);
    if (p[j0] != 0) continue;
    do {
      const std::size_t j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  std::vector<int> out(rows, -1);
  for (std::size_t j = 1; j <= cols; ++j) {
    if (p[j] != 0) out[p[j] - 1] = static_cast<int>(j - 1);
  }
  return out;
}

}  // namespace swarmform::shape_metrics
