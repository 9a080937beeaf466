#include "radar_ndt/evaluation/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <vector>

#include "radar_ndt/io/atomic_file.h"

namespace radar_ndt {
namespace {

struct Box {
  double x0, y0, w, h;  // pixel rectangle of a panel's plotting area
};

std::string esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '<')
      o += "&lt;";
    else if (c == '>')
      o += "&gt;";
    else if (c == '&')
      o += "&amp;";
    else
      o += c;
  }
  return o;
}

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof(b), "%.2f", v);
  return b;
}

/// A "nice" tick step for a range (1, 2 or 5 times a power of ten).
double tickStep(double range, int target = 6) {
  if (!(range > 0)) return 1;
  const double raw = range / target;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= raw) return m * p;
  return 10 * p;
}

/// One x-y chart: data ranges mapped into a pixel box, with axes, ticks and labels.
class Chart {
 public:
  Chart(std::ostringstream& out, Box box, double xmin, double xmax, double ymin, double ymax, bool equal_axes)
      : out_(out), box_(box) {
    if (!(xmax > xmin)) {
      xmin -= 1;
      xmax += 1;
    }
    if (!(ymax > ymin)) {
      ymin -= 1;
      ymax += 1;
    }
    if (equal_axes) {  // same metres per pixel on both axes, centred
      const double s = std::max((xmax - xmin) / box.w, (ymax - ymin) / box.h);
      const double cx = 0.5 * (xmin + xmax), cy = 0.5 * (ymin + ymax);
      xmin = cx - 0.5 * s * box.w;
      xmax = cx + 0.5 * s * box.w;
      ymin = cy - 0.5 * s * box.h;
      ymax = cy + 0.5 * s * box.h;
    }
    xmin_ = xmin;
    xmax_ = xmax;
    ymin_ = ymin;
    ymax_ = ymax;
  }
  double px(double x) const { return box_.x0 + (x - xmin_) / (xmax_ - xmin_) * box_.w; }
  double py(double y) const { return box_.y0 + box_.h - (y - ymin_) / (ymax_ - ymin_) * box_.h; }

  void axes(const std::string& xlabel, const std::string& ylabel) {
    out_ << "<rect x='" << num(box_.x0) << "' y='" << num(box_.y0) << "' width='" << num(box_.w) << "' height='"
         << num(box_.h) << "' fill='none' stroke='#444'/>\n";
    const double sx = tickStep(xmax_ - xmin_), sy = tickStep(ymax_ - ymin_);
    for (double t = std::ceil(xmin_ / sx) * sx; t <= xmax_ + 1e-9; t += sx) {
      out_ << "<line x1='" << num(px(t)) << "' y1='" << num(box_.y0 + box_.h) << "' x2='" << num(px(t)) << "' y2='"
           << num(box_.y0) << "' stroke='#ddd'/>\n";
      out_ << "<text x='" << num(px(t)) << "' y='" << num(box_.y0 + box_.h + 14)
           << "' font-size='11' text-anchor='middle'>" << label(t, sx) << "</text>\n";
    }
    for (double t = std::ceil(ymin_ / sy) * sy; t <= ymax_ + 1e-9; t += sy) {
      out_ << "<line x1='" << num(box_.x0) << "' y1='" << num(py(t)) << "' x2='" << num(box_.x0 + box_.w) << "' y2='"
           << num(py(t)) << "' stroke='#ddd'/>\n";
      out_ << "<text x='" << num(box_.x0 - 4) << "' y='" << num(py(t) + 4) << "' font-size='11' text-anchor='end'>"
           << label(t, sy) << "</text>\n";
    }
    out_ << "<text x='" << num(box_.x0 + box_.w / 2) << "' y='" << num(box_.y0 + box_.h + 32)
         << "' font-size='12' text-anchor='middle'>" << esc(xlabel) << "</text>\n";
    out_ << "<text x='" << num(box_.x0 - 48) << "' y='" << num(box_.y0 + box_.h / 2)
         << "' font-size='12' text-anchor='middle' transform='rotate(-90 " << num(box_.x0 - 48) << " "
         << num(box_.y0 + box_.h / 2) << ")'>" << esc(ylabel) << "</text>\n";
  }

  void polyline(const std::vector<double>& xs, const std::vector<double>& ys, const std::string& color,
                double width = 1.5) {
    out_ << "<polyline fill='none' stroke='" << color << "' stroke-width='" << width << "' points='";
    for (std::size_t i = 0; i < xs.size(); ++i) out_ << num(px(xs[i])) << ',' << num(py(ys[i])) << ' ';
    out_ << "'/>\n";
  }

  void markers(const std::vector<double>& xs, const std::vector<double>& ys, const std::string& color) {
    for (std::size_t i = 0; i < xs.size(); ++i)
      out_ << "<circle cx='" << num(px(xs[i])) << "' cy='" << num(py(ys[i])) << "' r='3' fill='" << color << "'/>\n";
  }

  void legend(int row, const std::string& text, const std::string& color) {
    const double y = box_.y0 + 14 + 16 * row;
    out_ << "<line x1='" << num(box_.x0 + 8) << "' y1='" << num(y - 4) << "' x2='" << num(box_.x0 + 28) << "' y2='"
         << num(y - 4) << "' stroke='" << color << "' stroke-width='2'/>\n";
    out_ << "<text x='" << num(box_.x0 + 32) << "' y='" << num(y) << "' font-size='12'>" << esc(text) << "</text>\n";
  }

 private:
  static std::string label(double v, double step) {
    char b[32];
    const int decimals = step >= 1 ? 0 : static_cast<int>(std::ceil(-std::log10(step)));
    std::snprintf(b, sizeof(b), "%.*f", decimals, std::abs(v) < 1e-12 ? 0.0 : v);
    return b;
  }
  std::ostringstream& out_;
  Box box_;
  double xmin_, xmax_, ymin_, ymax_;
};

void range(const std::vector<double>& v, double& lo, double& hi) {
  for (double x : v) {
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
}

/// Panel 1: the top view of both trajectories, equal axes, the start marked.
void topView(std::ostringstream& out, const PosePairs& pairs) {
  std::vector<double> gx, gy, ex, ey;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    gx.push_back(pairs.gt[i].translation().x());
    gy.push_back(pairs.gt[i].translation().y());
    ex.push_back(pairs.est[i].translation().x());
    ey.push_back(pairs.est[i].translation().y());
  }
  double xmin = std::numeric_limits<double>::max(), xmax = -xmin, ymin = xmin, ymax = -xmin;
  range(gx, xmin, xmax);
  range(ex, xmin, xmax);
  range(gy, ymin, ymax);
  range(ey, ymin, ymax);
  Chart top(out, Box{70, 40, 500, 500}, xmin, xmax, ymin, ymax, true);
  top.axes("x (m)", "y (m)");
  top.polyline(gx, gy, "#1f77b4");
  top.polyline(ex, ey, "#d62728");
  if (!gx.empty()) {
    out << "<circle cx='" << num(top.px(gx[0])) << "' cy='" << num(top.py(gy[0]))
        << "' r='6' fill='none' stroke='black' stroke-width='2'/>\n";
    out << "<text x='" << num(top.px(gx[0]) + 9) << "' y='" << num(top.py(gy[0]) - 9)
        << "' font-size='12'>start</text>\n";
  }
  top.legend(0, "ground truth", "#1f77b4");
  top.legend(1, "estimate", "#d62728");
}

/// Panel 2 with KITTI errors: translation and rotation error by segment length.
void kittiErrors(std::ostringstream& out, const SegmentError& kitti) {
  std::vector<double> L, te, re;
  for (const auto& pl : kitti.per_length)
    if (pl.segments > 0) {
      L.push_back(pl.length);
      te.push_back(pl.trans_err_pct);
      re.push_back(pl.rot_err_deg_per_m * 100.0);
    }
  double l0 = 0, l1 = 1, t0 = 0, t1 = 1e-9, r0 = 0, r1 = 1e-9;
  if (!L.empty()) {
    l0 = L.front();
    l1 = L.back();
  }
  range(te, t0, t1);
  range(re, r0, r1);
  Chart ct(out, Box{700, 40, 460, 210}, l0, l1, 0, t1 * 1.1, false);
  ct.axes("segment length (m)", "translation (%)");
  ct.polyline(L, te, "#d62728");
  ct.markers(L, te, "#d62728");
  Chart cr(out, Box{700, 330, 460, 210}, l0, l1, 0, r1 * 1.1, false);
  cr.axes("segment length (m)", "rotation (deg/100 m)");
  cr.polyline(L, re, "#9467bd");
  cr.markers(L, re, "#9467bd");
}

/// Panel 2 without them: the frame-to-frame translation error by pose.
void frameErrors(std::ostringstream& out, const PosePairs& pairs) {
  std::vector<double> idx, err;
  for (std::size_t i = 0; i + 1 < pairs.size(); ++i) {
    const Eigen::Isometry3d d_gt = pairs.gt[i].inverse() * pairs.gt[i + 1];
    const Eigen::Isometry3d d_est = pairs.est[i].inverse() * pairs.est[i + 1];
    idx.push_back(static_cast<double>(i));
    err.push_back((d_est.inverse() * d_gt).translation().norm());
  }
  double i0 = 0, i1 = 1, e0 = 0, e1 = 1e-9;
  range(idx, i0, i1);
  range(err, e0, e1);
  Chart c(out, Box{700, 40, 460, 500}, i0, i1, 0, e1 * 1.1, false);
  c.axes("pose index", "frame-to-frame translation error (m)");
  c.polyline(idx, err, "#d62728", 1.0);
}

/// Panel 3 of a 6-DoF evaluation: the side view, both heights over the distance the ground truth
/// has travelled (pose by pose, as given: the estimate's height drift shows as it grows).
void sideView(std::ostringstream& out, const PosePairs& pairs, Box box) {
  std::vector<double> dist, gz, ez;
  double d = 0;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (i > 0) d += (pairs.gt[i].translation() - pairs.gt[i - 1].translation()).norm();
    dist.push_back(d);
    gz.push_back(pairs.gt[i].translation().z());
    ez.push_back(pairs.est[i].translation().z());
  }
  double zmin = std::numeric_limits<double>::max(), zmax = -zmin;
  range(gz, zmin, zmax);
  range(ez, zmin, zmax);
  const double pad = std::max(0.05 * (zmax - zmin), 0.5);
  Chart c(out, box, 0, std::max(d, 1e-9), zmin - pad, zmax + pad, false);
  c.axes("distance travelled (m)", "height z (m)");
  c.polyline(dist, gz, "#1f77b4");
  c.polyline(dist, ez, "#d62728");
  c.legend(0, "ground truth", "#1f77b4");
  c.legend(1, "estimate", "#d62728");
}

}  // namespace

void writeEvaluationSvg(const std::string& path, const PosePairs& pairs, const EvaluationReport& report,
                        const std::string& title) {
  const bool six_dof = report.ate_se3.has_value();  // a 6-DoF run's evaluation: its side view below
  const double W = 1200, H = six_dof ? 900 : 600;
  std::ostringstream out;
  out << "<?xml version='1.0' encoding='UTF-8'?>\n<svg xmlns='http://www.w3.org/2000/svg' width='" << W << "' height='"
      << H << "' viewBox='0 0 " << W << ' ' << H << "' font-family='sans-serif'>\n";
  out << "<rect width='100%' height='100%' fill='white'/>\n";
  out << "<text x='" << W / 2 << "' y='22' font-size='16' text-anchor='middle'>" << esc(title) << "</text>\n";
  topView(out, pairs);
  if (report.kitti && !report.kitti->per_length.empty())
    kittiErrors(out, *report.kitti);
  else
    frameErrors(out, pairs);
  if (six_dof) sideView(out, pairs, Box{70, 630, 1090, 220});
  out << "</svg>\n";
  writeFileAtomically(path, out.str());
}

}  // namespace radar_ndt
