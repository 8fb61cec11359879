// Latency estimation (latency_estimation.h): profile of a least-squares fit around the start of
// motion over a grid of delay candidates, profile-likelihood interval for the uncertainty.
#include "predvs/calibration/latency_estimation.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double median(std::vector<double> v) {
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// p(t) = integral of the zero-order-held command from the first tick (0 before it).
class CommandIntegral {
 public:
  CommandIntegral(const std::vector<double>& t, const std::vector<std::vector<double>>& u, double last_dt)
      : t_(t), u_(u) {
    const size_t m = u.front().size();
    P_.assign(t.size(), Eigen::VectorXd::Zero(static_cast<Eigen::Index>(m)));
    for (size_t k = 1; k < t.size(); ++k)
      for (size_t i = 0; i < m; ++i) P_[k](static_cast<Eigen::Index>(i)) = P_[k - 1](static_cast<Eigen::Index>(i)) + u[k - 1][i] * (t[k] - t[k - 1]);
    end_ = t.back() + last_dt;
  }
  Eigen::VectorXd at(double time) const {
    const Eigen::Index m = P_.front().size();
    if (time <= t_.front()) return Eigen::VectorXd::Zero(m);
    const double tc = std::min(time, end_);
    const size_t k = static_cast<size_t>(std::upper_bound(t_.begin(), t_.end(), tc) - t_.begin()) - 1;
    Eigen::VectorXd p = P_[k];
    for (Eigen::Index i = 0; i < m; ++i) p(i) += u_[k][static_cast<size_t>(i)] * (tc - t_[k]);
    return p;
  }

 private:
  const std::vector<double>& t_;
  const std::vector<std::vector<double>>& u_;
  std::vector<Eigen::VectorXd> P_;
  double end_ = 0.0;
};

/// Residual sum of squares of the least-squares fit y ~ X (rank-revealing QR).
double rssOf(const Eigen::MatrixXd& X, const Eigen::VectorXd& y) {
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(X);
  const Eigen::VectorXd beta = qr.solve(y);
  return (y - X * beta).squaredNorm();
}

struct Profile {
  std::vector<double> grid;
  std::vector<std::vector<double>> rss_w;  ///< [window][grid] (one window: the start of motion)
  std::vector<double> rss_base_w;          ///< per window: RSS of the polynomial in time alone
  int frames = 0;
  int directions = 0;          ///< principal directions of the motion used as regressors
  int params_per_channel = 0;
};

/// RSS of every window at every grid delay, the frames timed by `frame_t`.
Profile profile(const LatencyLog& log, const std::vector<double>& frame_t, const CommandIntegral& p,
                const LatencyOptions& o, double step) {
  Profile pr;
  for (double L = 0.0; L <= o.max_delay_s + 1e-12; L += step) pr.grid.push_back(L);
  const size_t m = log.command.front().size(), n = log.features.front().size();
  // The start of motion: the first tick with a non-zero command.
  size_t k0 = 0;
  while (k0 < log.command.size() && std::all_of(log.command[k0].begin(), log.command[k0].end(), [](double u) { return u == 0.0; })) ++k0;
  if (k0 == log.command.size()) return pr;
  const double t_start = log.tick_t_s[k0];
  // One window: every frame up to the start + max delay + window_s.
  std::vector<size_t> w;
  for (size_t j = 0; j < frame_t.size(); ++j)
    if (frame_t[j] <= t_start + o.max_delay_s + o.window_s) w.push_back(j);
  // The directions the robot actually moved in over the window (principal directions of p at the
  // ticks, those with a singular value >= 5 % of the largest): the regression on them only, so
  // that directions barely excited cannot fit noise.
  const double t_end = t_start + o.max_delay_s + o.window_s;
  std::vector<Eigen::VectorXd> ps;
  for (size_t k = 0; k < log.tick_t_s.size() && log.tick_t_s[k] <= t_end; ++k) ps.push_back(p.at(log.tick_t_s[k]));
  Eigen::MatrixXd Pm(static_cast<Eigen::Index>(ps.size()), static_cast<Eigen::Index>(m));
  for (size_t k = 0; k < ps.size(); ++k) Pm.row(static_cast<Eigen::Index>(k)) = ps[k].transpose();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(Pm, Eigen::ComputeThinV);
  const Eigen::VectorXd sv = svd.singularValues();
  Eigen::Index kept = 0;
  while (kept < sv.size() && sv(kept) >= 0.05 * sv(0) && sv(kept) > 0.0) ++kept;
  const Eigen::MatrixXd V = svd.matrixV().leftCols(std::max<Eigen::Index>(kept, 1));
  const size_t md = static_cast<size_t>(V.cols());
  pr.directions = static_cast<int>(md);
  const size_t trend = static_cast<size_t>(o.time_order) + 1;
  const size_t params = md + trend;
  pr.params_per_channel = static_cast<int>(params);
  if (w.size() < params + 3) return pr;
  const double t0 = frame_t[w.front()];
  std::vector<double> rss(pr.grid.size(), 0.0);
  double base = 0.0;
  bool any = false;
  for (size_t c = 0; c < n; ++c) {
    std::vector<size_t> rows;
    for (size_t j : w)
      if (std::isfinite(log.features[j][c])) rows.push_back(j);
    if (rows.size() < params + 3) continue;
    any = true;
    const Eigen::Index nr = static_cast<Eigen::Index>(rows.size()), nt = static_cast<Eigen::Index>(trend);
    Eigen::VectorXd y(nr);
    Eigen::MatrixXd line(nr, nt);
    for (Eigen::Index r = 0; r < nr; ++r) {
      y(r) = log.features[rows[static_cast<size_t>(r)]][c];
      const double dt = frame_t[rows[static_cast<size_t>(r)]] - t0;
      for (Eigen::Index q = 0; q < nt; ++q) line(r, q) = std::pow(dt, static_cast<double>(q));
    }
    base += rssOf(line, y);
    for (size_t g = 0; g < pr.grid.size(); ++g) {
      Eigen::MatrixXd X(nr, static_cast<Eigen::Index>(params));
      X.leftCols(nt) = line;
      for (Eigen::Index r = 0; r < nr; ++r)
        X.block(r, nt, 1, static_cast<Eigen::Index>(md)) = (V.transpose() * p.at(frame_t[rows[static_cast<size_t>(r)]] - pr.grid[g])).transpose();
      rss[g] += rssOf(X, y);
    }
  }
  if (!any) return pr;
  pr.rss_w.push_back(rss);
  pr.rss_base_w.push_back(base);
  pr.frames = static_cast<int>(w.size());
  return pr;
}

/// The point model (latency_estimation.h): windows over the whole log, depths and target
/// velocities fitted per window, the rotation part fixed by the geometry.
Profile profilePoints(const LatencyLog& log, const std::vector<double>& frame_t, const CommandIntegral& p,
                      const LatencyOptions& o, double step) {
  Profile pr;
  for (double L = 0.0; L <= o.max_delay_s + 1e-12; L += step) pr.grid.push_back(L);
  const size_t n = log.features.front().size(), points = n / 2;
  const size_t order = static_cast<size_t>(std::max(1, o.time_order));
  // Windows of consecutive frames where every feature is seen (a lost point ends a window).
  std::vector<std::vector<size_t>> windows;
  auto seen = [&](size_t j) {
    return std::all_of(log.features[j].begin(), log.features[j].end(), [](double v) { return std::isfinite(v); });
  };
  for (size_t j = 0; j < frame_t.size();) {
    if (!seen(j)) {
      ++j;
      continue;
    }
    const double start = frame_t[j];
    std::vector<size_t> w;
    while (j < frame_t.size() && seen(j) && frame_t[j] < start + o.point_window_s) w.push_back(j++);
    windows.push_back(w);
  }
  // Levels: s_j = b + sum over the window's increments up to j of (model increment), so that the
  // noise of s_j enters one row only (increments would correlate with the loop's response to it).
  const size_t per_channel = 1 + order;
  const size_t params = points + n * per_channel;
  pr.params_per_channel = static_cast<int>((params + n - 1) / n);
  pr.directions = 6;
  for (const auto& w : windows) {
    if (w.size() * n < params + 3 || w.size() < 3) continue;
    const double t0 = frame_t[w.front()];
    const Eigen::Index nr = static_cast<Eigen::Index>(w.size() * n);
    Eigen::VectorXd y0(nr);
    Eigen::MatrixXd T = Eigen::MatrixXd::Zero(nr, static_cast<Eigen::Index>(n * per_channel));
    std::vector<double> trend(n * order, 0.0);
    for (size_t k = 0; k < w.size(); ++k) {
      const size_t j = w[k];
      if (k > 0) {
        const double dtau = frame_t[j] - frame_t[w[k - 1]], mid = 0.5 * (frame_t[j] + frame_t[w[k - 1]]) - t0;
        for (size_t c = 0; c < n; ++c)
          for (size_t q = 0; q < order; ++q) trend[c * order + q] += dtau * std::pow(mid, static_cast<double>(q));
      }
      for (size_t c = 0; c < n; ++c) {
        const Eigen::Index r = static_cast<Eigen::Index>(k * n + c);
        y0(r) = log.features[j][c];
        T(r, static_cast<Eigen::Index>(c * per_channel)) = 1.0;
        for (size_t q = 0; q < order; ++q) T(r, static_cast<Eigen::Index>(c * per_channel + 1 + q)) = trend[c * order + q];
      }
    }
    pr.rss_base_w.push_back(rssOf(T, y0));
    std::vector<double> rss(pr.grid.size(), 0.0);
    for (size_t g = 0; g < pr.grid.size(); ++g) {
      const double L = pr.grid[g];
      Eigen::MatrixXd X(nr, static_cast<Eigen::Index>(params));
      X.leftCols(static_cast<Eigen::Index>(points)).setZero();
      X.rightCols(T.cols()) = T;
      Eigen::VectorXd y = y0;
      std::vector<double> depth_term(n, 0.0), known(n, 0.0);
      for (size_t k = 0; k < w.size(); ++k) {
        const size_t j = w[k];
        if (k > 0) {
          const size_t jp = w[k - 1];
          const Eigen::VectorXd d = p.at(frame_t[j] - L) - p.at(frame_t[jp] - L);  // V (3), W (3)
          for (size_t i = 0; i < points; ++i) {
            const double x = (log.features[jp][2 * i] - o.u0) / o.px, yy = (log.features[jp][2 * i + 1] - o.v0) / o.py;
            depth_term[2 * i] += o.px * (-d(0) + x * d(2));
            known[2 * i] += o.px * (x * yy * d(3) - (1.0 + x * x) * d(4) + yy * d(5));
            depth_term[2 * i + 1] += o.py * (-d(1) + yy * d(2));
            known[2 * i + 1] += o.py * ((1.0 + yy * yy) * d(3) - x * yy * d(4) - x * d(5));
          }
        }
        for (size_t c = 0; c < n; ++c) {
          const Eigen::Index r = static_cast<Eigen::Index>(k * n + c);
          X(r, static_cast<Eigen::Index>(c / 2)) = depth_term[c];
          y(r) -= known[c];
        }
      }
      rss[g] = rssOf(X, y);
    }
    pr.rss_w.push_back(rss);
    pr.frames += static_cast<int>(w.size());
  }
  return pr;
}

/// Argmin of a profile, refined by the parabola through the lowest point and its neighbours.
double argminRefined(const std::vector<double>& grid, const std::vector<double>& rss) {
  const size_t g = static_cast<size_t>(std::min_element(rss.begin(), rss.end()) - rss.begin());
  if (g == 0 || g + 1 == rss.size()) return grid[g];
  const double a = rss[g - 1], b = rss[g], c = rss[g + 1];
  const double den = a - 2.0 * b + c;
  if (!(den > 0.0)) return grid[g];
  const double shift = 0.5 * (a - c) / den;  // in grid steps, within [-0.5, 0.5]
  return grid[g] + shift * (grid[g + 1] - grid[g]);
}

DelayEstimate estimate(const LatencyLog& log, const std::vector<double>& frame_t, const CommandIntegral& p,
                       const LatencyOptions& o, double step, const std::string& what) {
  const Profile pr = o.point_model ? profilePoints(log, frame_t, p, o, step) : profile(log, frame_t, p, o, step);
  const size_t W = pr.rss_w.size();
  if (W < 1)
    throw std::invalid_argument(what + ": too few frames from the start of the log to " + std::to_string(o.max_delay_s + o.window_s) +
                                " s after the start of motion (need more than " +
                                std::to_string(log.command.front().size() + static_cast<size_t>(o.time_order) + 4) +
                                "; a longer log, a larger --window-s, or a log that starts at rest)");
  DelayEstimate e;
  e.grid_s = pr.grid;
  e.rss.assign(pr.grid.size(), 0.0);
  double base = 0.0;
  for (size_t w = 0; w < W; ++w) {
    base += pr.rss_base_w[w];
    for (size_t g = 0; g < pr.grid.size(); ++g) e.rss[g] += pr.rss_w[w][g];
  }
  const auto [lo, hi] = std::minmax_element(e.rss.begin(), e.rss.end());
  if (!(*hi - *lo > 1e-9 * std::max(*hi, 1e-300)))
    throw std::invalid_argument(what + ": the fit does not depend on the delay (the command's variations do not show in the features)");
  const size_t g_min = static_cast<size_t>(lo - e.rss.begin());
  if (g_min + 1 == e.rss.size())
    throw std::invalid_argument(what + ": the best delay is at the end of the searched range (" + std::to_string(o.max_delay_s) +
                                " s): raise --max-delay-s");
  e.delay_s = argminRefined(e.grid_s, e.rss);
  e.windows = static_cast<int>(W);
  e.frames = pr.frames;
  e.directions = pr.directions;
  e.explained = base > 0.0 ? 1.0 - *lo / base : 0.0;
  // Profile-likelihood interval: the delays whose RSS exceeds the minimum by at most one residual
  // variance (chi-square with one degree of freedom at 1, i.e. one standard deviation).
  const double params = static_cast<double>(W * log.features.front().size() * static_cast<size_t>(pr.params_per_channel));  // point model: rounded up
  const double dof = std::max(1.0, static_cast<double>(pr.frames) * static_cast<double>(log.features.front().size()) - params);
  const double level = *lo + *lo / dof;
  size_t first = g_min, last = g_min;
  for (size_t g = 0; g < e.rss.size(); ++g)
    if (e.rss[g] <= level) first = std::min(first, g), last = std::max(last, g);
  auto crossing = [&](size_t g, int dir) {
    const long h = static_cast<long>(g) + dir;
    if (h < 0 || h >= static_cast<long>(e.rss.size())) return e.grid_s[g];
    const double r0 = e.rss[g], r1 = e.rss[static_cast<size_t>(h)];
    const double f = r1 > r0 ? (level - r0) / (r1 - r0) : 0.0;
    return e.grid_s[g] + f * (e.grid_s[static_cast<size_t>(h)] - e.grid_s[g]);
  };
  e.lo_s = crossing(first, -1);
  e.hi_s = crossing(last, +1);
  e.sigma_s = std::max(0.5 * (e.hi_s - e.lo_s), step / std::sqrt(12.0));
  return e;
}

}  // namespace

LatencyResult estimateLatency(const LatencyLog& log, const LatencyOptions& o) {
  if (!(o.max_delay_s > 0.0) || !std::isfinite(o.max_delay_s)) throw std::invalid_argument("max delay must be > 0 s");
  if (!(o.window_s > 0.0) || !std::isfinite(o.window_s)) throw std::invalid_argument("window must be > 0 s");
  if (!(o.step_s >= 0.0)) throw std::invalid_argument("grid step must be >= 0 s");
  const size_t K = log.tick_t_s.size(), F = log.frame_delivery_s.size();
  if (K < 2) throw std::invalid_argument("the log has fewer than 2 control ticks");
  if (F < 2) throw std::invalid_argument("the log has fewer than 2 frames (no feature ever changes)");
  if (log.command.size() != K || log.features.size() != F ||
      (!log.frame_acquisition_s.empty() && log.frame_acquisition_s.size() != F))
    throw std::invalid_argument("latency log: the per-tick and per-frame arrays disagree in size");
  const size_t m = log.command.front().size(), n = log.features.front().size();
  if (m == 0) throw std::invalid_argument("the log has no command column");
  if (n == 0) throw std::invalid_argument("the log has no feature column");
  for (size_t k = 1; k < K; ++k)
    if (!(log.tick_t_s[k] > log.tick_t_s[k - 1])) throw std::invalid_argument("control tick times are not strictly increasing");
  for (size_t j = 1; j < F; ++j)
    if (!(log.frame_delivery_s[j] > log.frame_delivery_s[j - 1]))
      throw std::invalid_argument("frame delivery times are not strictly increasing");
  bool command_varies = false;
  for (size_t i = 0; i < m && !command_varies; ++i)
    for (size_t k = 1; k < K; ++k) {
      if (log.command[k].size() != m) throw std::invalid_argument("latency log: a tick has the wrong number of command components");
      if (log.command[k][i] != log.command[0][i]) {
        command_varies = true;
        break;
      }
    }
  if (!command_varies) throw std::invalid_argument("the command never changes: a constant command carries no information on the delay");
  bool features_vary = false;
  for (size_t c = 0; c < n && !features_vary; ++c) {
    double first = kNaN;
    for (size_t j = 0; j < F; ++j) {
      const double v = log.features[j][c];
      if (!std::isfinite(v)) continue;
      if (!std::isfinite(first)) first = v;
      else if (v != first) {
        features_vary = true;
        break;
      }
    }
  }
  if (!features_vary) throw std::invalid_argument("the features never change: the log shows no motion");

  LatencyResult r;
  std::vector<double> dt;
  for (size_t k = 1; k < K; ++k) dt.push_back(log.tick_t_s[k] - log.tick_t_s[k - 1]);
  r.base_period_s = median(dt);
  std::vector<double> df;
  for (size_t j = 1; j < F; ++j) df.push_back(log.frame_delivery_s[j] - log.frame_delivery_s[j - 1]);
  r.frame_period_s = median(df);
  const double step = o.step_s > 0.0 ? o.step_s : r.base_period_s / 10.0;
  if (o.point_model) {
    if (m != 6) throw std::invalid_argument("the point model needs a camera twist (6 command columns vx vy vz wx wy wz), got " + std::to_string(m));
    if (n % 2 != 0) throw std::invalid_argument("the point model needs image points (u, v pairs), got " + std::to_string(n) + " features");
    if (!(o.px > 0.0) || !(o.py > 0.0)) throw std::invalid_argument("the point model needs focal lengths px, py > 0");
  }
  const CommandIntegral p(log.tick_t_s, log.command, r.base_period_s);

  r.total = estimate(log, log.frame_delivery_s, p, o, step, "delivery-time fit");
  r.vision_delay_s = r.total.delay_s;
  r.vision_sigma_s = r.total.sigma_s;
  r.stamped_delay_s = kNaN;
  if (!log.frame_acquisition_s.empty()) {
    std::vector<double> d;
    for (size_t j = 0; j < F; ++j) d.push_back(log.frame_delivery_s[j] - log.frame_acquisition_s[j]);
    r.stamped_delay_s = median(d);
    r.has_actuation = true;
    r.actuation = estimate(log, log.frame_acquisition_s, p, o, step, "acquisition-time fit");
    r.vision_delay_s = r.total.delay_s - r.actuation.delay_s;
    r.vision_sigma_s = std::hypot(r.total.sigma_s, r.actuation.sigma_s);
  }
  return r;
}

}  // namespace predvs
