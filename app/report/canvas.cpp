#include "canvas.hpp"

#include "millnet/core/atomic_file.hpp"
#include "millnet/core/error.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

namespace millnet::report {

std::array<double, 2> Layout::to_pixel(double x, double y) const {
  auto map = [](double v, double lo, double hi, bool log, double p0, double p1) {
    if (log) {
      v = std::log10(v);
      lo = std::log10(lo);
      hi = std::log10(hi);
    }
    return p0 + (v - lo) / (hi - lo) * (p1 - p0);
  };
  return {map(x, x_min, x_max, log_x, plot_left, plot_right), map(y, y_min, y_max, log_y, plot_bottom, plot_top)};
}

std::array<unsigned char, 3> viridis_rgb(double t) {
  // 256-entry table made once from OpenCV's own viridis map, then linear interpolation (rounded),
  // so colours depend only on t.
  static const cv::Mat lut = [] {
    cv::Mat ramp(1, 256, CV_8UC1);
    for (int i = 0; i < 256; ++i) ramp.at<unsigned char>(0, i) = static_cast<unsigned char>(i);
    cv::Mat out;
    cv::applyColorMap(ramp, out, cv::COLORMAP_VIRIDIS);
    return out;
  }();
  if (!(t >= 0)) t = 0;  // also NaN
  if (t > 1) t = 1;
  const double f = t * 255.0;
  const int i0 = std::min(254, static_cast<int>(std::floor(f)));
  const double w = f - i0;
  const cv::Vec3b a = lut.at<cv::Vec3b>(0, i0), b = lut.at<cv::Vec3b>(0, i0 + 1);
  auto mix = [&](int c) { return static_cast<unsigned char>(std::lround((1 - w) * a[c] + w * b[c])); };
  return {mix(2), mix(1), mix(0)};  // BGR → RGB
}

namespace detail {

cv::Scalar series_colour(std::size_t i) {
  // Okabe & Ito (2008), without yellow (too pale on white) first: blue, vermillion, bluish
  // green, reddish purple, orange, sky blue, black, yellow. Stored BGR.
  static const cv::Scalar p[] = {{178, 114, 0}, {0, 94, 213},   {115, 158, 0}, {167, 121, 204},
                                 {0, 159, 230}, {233, 180, 86}, {0, 0, 0},     {66, 228, 240}};
  return p[i % (sizeof p / sizeof p[0])];
}

cv::Scalar viridis(double t) {
  const auto c = viridis_rgb(t);
  return {static_cast<double>(c[2]), static_cast<double>(c[1]), static_cast<double>(c[0])};
}

std::string ascii(std::string_view s) {
  static const std::pair<std::string_view, std::string_view> table[] = {
      {"α", "alpha"}, {"β", "beta"}, {"γ", "gamma"}, {"σ", "sigma"}, {"μ", "u"},   {"Δ", "d"},
      {"²", "^2"},    {"³", "^3"},   {"₀", "0"},     {"₁", "1"},     {"₂", "2"},   {"₃", "3"},
      {"°", " deg"},  {"×", "x"},    {"·", "*"},     {"—", "-"},     {"–", "-"},   {"−", "-"},
      {"≤", "<="},    {"≥", ">="},   {"±", "+/-"},   {"→", "->"},    {"…", "..."}, {"≈", "~"},
      {"√", "sqrt"},  {"ø", "d"},    {"Ø", "D"},     {"’", "'"},     {"“", "\""},  {"”", "\""}};
  std::string out;
  out.reserve(s.size());
  std::size_t i = 0;
  while (i < s.size()) {  // O(|s|·|table|)
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x80) {
      out += c >= 0x20 ? static_cast<char>(c) : ' ';  // control characters (also newlines) become spaces
      ++i;
      continue;
    }
    bool found = false;
    for (const auto& [from, to] : table) {
      if (s.substr(i, from.size()) == from) {
        out += to;
        i += from.size();
        found = true;
        break;
      }
    }
    if (found) continue;
    // Unknown code point: skip its continuation bytes, draw one '?'.
    ++i;
    while (i < s.size() && (static_cast<unsigned char>(s[i]) & 0xC0) == 0x80) ++i;
    out += '?';
  }
  return out;
}

namespace {
constexpr int kFace = cv::FONT_HERSHEY_SIMPLEX;
constexpr int kShift = 4;
constexpr double kFix = 16.0;  // 2^kShift
cv::Point fix(cv::Point2d p) { return {cvRound(p.x * kFix), cvRound(p.y * kFix)}; }
}  // namespace

cv::Size text_size(const std::string& text, Font font) {
  int baseline = 0;
  return cv::getTextSize(ascii(text), kFace, font.scale, font.thickness, &baseline);
}

void put_text(cv::Mat& img, const std::string& text, cv::Point at, Font font, const cv::Scalar& colour, HAlign h,
              VAlign v) {
  const std::string t = ascii(text);
  int baseline = 0;
  const cv::Size sz = cv::getTextSize(t, kFace, font.scale, font.thickness, &baseline);
  if (h == HAlign::Center) at.x -= sz.width / 2;
  if (h == HAlign::Right) at.x -= sz.width;
  if (v == VAlign::Top) at.y += sz.height;
  if (v == VAlign::Middle) at.y += sz.height / 2;
  cv::putText(img, t, at, kFace, font.scale, colour, font.thickness, cv::LINE_AA);
}

void put_text_vertical(cv::Mat& img, const std::string& text, cv::Point centre, Font font, const cv::Scalar& colour) {
  const std::string t = ascii(text);
  int baseline = 0;
  const cv::Size sz = cv::getTextSize(t, kFace, font.scale, font.thickness, &baseline);
  cv::Mat tmp(sz.height + baseline + 4, sz.width + 4, img.type(), kWhite);
  cv::putText(tmp, t, {2, sz.height + 2}, kFace, font.scale, colour, font.thickness, cv::LINE_AA);
  cv::Mat rot;
  cv::rotate(tmp, rot, cv::ROTATE_90_COUNTERCLOCKWISE);
  cv::Rect dst(centre.x - rot.cols / 2, centre.y - rot.rows / 2, rot.cols, rot.rows);
  const cv::Rect clipped = dst & cv::Rect(0, 0, img.cols, img.rows);
  if (clipped.empty()) return;
  const cv::Rect src(clipped.x - dst.x, clipped.y - dst.y, clipped.width, clipped.height);
  // Dark text on a white tile: the per-channel minimum composes it onto the picture.
  cv::Mat roi = img(clipped);
  cv::min(roi, rot(src), roi);
}

std::vector<std::string> wrap(const std::string& text, Font font, int max_width) {
  std::vector<std::string> lines;
  std::string cur;
  std::size_t i = 0;
  const std::string t = ascii(text);
  while (i <= t.size()) {  // O(|text|) words, each measured once per line candidate
    std::size_t j = t.find(' ', i);
    if (j == std::string::npos) j = t.size();
    const std::string word = t.substr(i, j - i);
    if (!word.empty()) {
      const std::string cand = cur.empty() ? word : cur + " " + word;
      if (!cur.empty() && text_size(cand, font).width > max_width) {
        lines.push_back(cur);
        cur = word;
      } else {
        cur = cand;
      }
    }
    i = j + 1;
  }
  if (!cur.empty()) lines.push_back(cur);
  return lines;
}

void line(cv::Mat& img, cv::Point2d a, cv::Point2d b, const cv::Scalar& colour, int thickness) {
  cv::line(img, fix(a), fix(b), colour, thickness, cv::LINE_AA, kShift);
}

void polyline(cv::Mat& img, const std::vector<cv::Point2d>& pts, const cv::Scalar& colour, int thickness) {
  if (pts.size() < 2) return;
  std::vector<cv::Point> p;
  p.reserve(pts.size());
  for (const auto& q : pts) p.push_back(fix(q));
  cv::polylines(img, p, false, colour, thickness, cv::LINE_AA, kShift);
}

void dashed_polyline(cv::Mat& img, const std::vector<cv::Point2d>& pts, const cv::Scalar& colour, int thickness,
                     double dash_px, double gap_px) {
  // Walk the polyline once (O(points + dashes)), alternating "on" for dash_px and "off" for gap_px.
  bool on = true;
  double left = dash_px;
  for (std::size_t k = 0; k + 1 < pts.size(); ++k) {
    cv::Point2d a = pts[k];
    const cv::Point2d b = pts[k + 1];
    double seg = std::hypot(b.x - a.x, b.y - a.y);
    while (seg > 1e-9) {
      const double step = std::min(left, seg);
      const cv::Point2d c = a + (b - a) * (step / seg);
      if (on) line(img, a, c, colour, thickness);
      a = c;
      seg -= step;
      left -= step;
      if (left <= 1e-9) {
        on = !on;
        left = on ? dash_px : gap_px;
      }
    }
  }
}

void circle_at(cv::Mat& img, cv::Point2d c, double r, const cv::Scalar& colour, int thickness) {
  cv::circle(img, fix(c), cvRound(r * kFix), colour, thickness, cv::LINE_AA, kShift);
}

void fill_polygons(cv::Mat& img, const std::vector<std::vector<cv::Point2d>>& polys, const cv::Scalar& colour) {
  std::vector<std::vector<cv::Point>> p;
  for (const auto& poly : polys) {
    if (poly.size() < 3) continue;
    auto& q = p.emplace_back();
    for (const auto& v : poly) q.push_back(fix(v));
  }
  if (!p.empty()) cv::fillPoly(img, p, colour, cv::LINE_AA, kShift);
}

double Axis::to_px(double v) const {
  if (log) return p0 + (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo)) * (p1 - p0);
  return p0 + (v - lo) / (hi - lo) * (p1 - p0);
}

double nice_step(double lo, double hi, int target) {
  const double range = hi - lo;
  if (!(range > 0)) return 1;
  const double raw = range / std::max(1, target);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double n = raw / mag;
  return (n < 1.5 ? 1 : n < 3 ? 2 : n < 7 ? 5 : 10) * mag;
}

std::vector<double> nice_ticks(double lo, double hi, int target) {
  const double step = nice_step(lo, hi, target);
  std::vector<double> t;
  const double first = std::ceil(lo / step - 1e-9);
  for (int i = 0; i < 1000; ++i) {
    const double v = (first + i) * step;
    if (v > hi + step * 1e-9) break;
    t.push_back(std::abs(v) < step * 1e-9 ? 0.0 : v);
  }
  return t;
}

void nice_range(double& lo, double& hi, int target) {
  if (!(hi > lo)) {
    const double d = lo == 0 ? 1.0 : std::abs(lo) * 0.1;
    lo -= d;
    hi += d;
  }
  const double step = nice_step(lo, hi, target);
  lo = std::floor(lo / step + 1e-9) * step;
  hi = std::ceil(hi / step - 1e-9) * step;
}

void padded_nice_range(double& lo, double& hi, int target) {
  const double pad = 0.03 * (hi - lo);
  if (pad > 0) {
    lo = (lo >= 0 && lo - pad < 0) ? 0.0 : lo - pad;
    hi = (hi <= 0 && hi + pad > 0) ? 0.0 : hi + pad;
  }
  nice_range(lo, hi, target);
}

void log_range(double& lo, double& hi) {
  lo = std::pow(10.0, std::floor(std::log10(lo) + 1e-9));
  hi = std::pow(10.0, std::ceil(std::log10(hi) - 1e-9));
  if (!(hi > lo)) hi = lo * 10;
}

std::string tick_label(double v, double step) {
  if (std::abs(v) < std::abs(step) * 1e-9) v = 0;
  if (std::abs(v) >= 1e7) return compact_number(v, 3);
  const int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(std::abs(step)) + 1e-9)));
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

int widest_tick_label(double lo, double hi, int target) {
  int w = 0;
  const double step = nice_step(lo, hi, target);
  for (double v : nice_ticks(lo, hi, target)) w = std::max(w, text_size(tick_label(v, step), kTickFont).width);
  return w;
}

std::string compact_number(double v, int sig) {
  if (!std::isfinite(v)) return std::isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf");
  if (v == 0) return "0";
  const double a = std::abs(v);
  char buf[64];
  if (a >= 1e6 || a < 1e-3) {
    std::snprintf(buf, sizeof buf, "%.*e", std::max(0, sig - 1), v);
    std::string s = buf;  // trim "1.50e-04" → "1.5e-04"
    const auto e = s.find('e');
    std::string mant = s.substr(0, e), ex = s.substr(e);
    if (mant.find('.') != std::string::npos) {
      while (mant.back() == '0') mant.pop_back();
      if (mant.back() == '.') mant.pop_back();
    }
    return mant + ex;
  }
  const int decimals = std::max(0, sig - 1 - static_cast<int>(std::floor(std::log10(a))));
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  std::string s = buf;
  if (s.find('.') != std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  return s;
}

namespace {

struct Tick {
  double v;
  bool major;
  std::string label;
};

std::vector<Tick> axis_ticks(const Axis& a, int target) {
  std::vector<Tick> out;
  if (a.log) {
    const int k0 = static_cast<int>(std::lround(std::log10(a.lo)));
    const int k1 = static_cast<int>(std::lround(std::log10(a.hi)));
    const int every = std::max(1, (k1 - k0 + target - 1) / std::max(1, target));
    for (int k = k0; k <= k1; ++k) {
      const double d = std::pow(10.0, k);
      std::string lab;
      if ((k - k0) % every == 0) {
        if (k >= -3 && k <= 5) {
          lab = tick_label(d, d);
        } else {
          lab = "1e" + std::to_string(k);
        }
      }
      out.push_back({d, true, lab});
      if (k < k1 && every == 1)
        for (int m = 2; m <= 9; ++m) out.push_back({m * d, false, ""});
    }
    return out;
  }
  const double step = nice_step(a.lo, a.hi, target);
  for (double v : nice_ticks(a.lo, a.hi, target)) out.push_back({v, true, tick_label(v, step)});
  return out;
}

}  // namespace

void draw_axes(cv::Mat& img, const Axis& x, const Axis& y, const std::string& x_label, const std::string& y_label,
               const AxesStyle& style) {
  const double left = x.p0, right = x.p1, bottom = y.p0, top = y.p1;
  // Fewer ticks until neighbouring numbers no longer touch (narrow or short plots).
  auto crowded_x = [&](const std::vector<Tick>& t) {
    double prev_right = -1e9;
    for (const auto& k : t) {
      if (k.label.empty()) continue;
      const double w = text_size(k.label, kTickFont).width, c = x.to_px(k.v);
      if (c - w / 2 < prev_right + 8) return true;
      prev_right = c + w / 2;
    }
    return false;
  };
  auto crowded_y = [&](const std::vector<Tick>& t) {
    double prev = 1e9;
    for (const auto& k : t) {
      if (k.label.empty()) continue;
      const double c = y.to_px(k.v);
      if (std::abs(prev - c) < 20) return true;
      prev = c;
    }
    return false;
  };
  std::vector<Tick> xt, yt;
  if (style.x_ticks)
    for (int target = style.x_target;; target = target / 2) {
      xt = axis_ticks(x, target);
      if (target <= 1 || !crowded_x(xt)) break;
    }
  for (int target = style.y_target;; target = target / 2) {
    yt = axis_ticks(y, target);
    if (target <= 1 || !crowded_y(yt)) break;
  }
  if (style.grid) {
    for (const auto& t : xt)
      if (t.major) line(img, {x.to_px(t.v), top}, {x.to_px(t.v), bottom}, kGridGrey, 1);
    for (const auto& t : yt)
      if (t.major) line(img, {left, y.to_px(t.v)}, {right, y.to_px(t.v)}, kGridGrey, 1);
  }
  cv::rectangle(img, cv::Point(cvRound(left), cvRound(top)), cv::Point(cvRound(right), cvRound(bottom)), kAxisGrey, 1,
                cv::LINE_8);
  for (const auto& t : xt) {
    const double px = x.to_px(t.v);
    line(img, {px, bottom}, {px, bottom + (t.major ? 6 : 3)}, kAxisGrey, 1);
    if (style.x_numbers && !t.label.empty())
      put_text(img, t.label, {cvRound(px), cvRound(bottom) + 10}, kTickFont, kTextGrey, HAlign::Center, VAlign::Top);
  }
  int max_w = 0;
  for (const auto& t : yt) {
    const double py = y.to_px(t.v);
    line(img, {left - (t.major ? 6 : 3), py}, {left, py}, kAxisGrey, 1);
    if (!t.label.empty()) {
      put_text(img, t.label, {cvRound(left) - 9, cvRound(py)}, kTickFont, kTextGrey, HAlign::Right, VAlign::Middle);
      max_w = std::max(max_w, text_size(t.label, kTickFont).width);
    }
  }
  if (style.x_numbers && !x_label.empty())
    put_text(img, x_label, {cvRound((left + right) / 2), cvRound(bottom) + 34}, kLabelFont, kBlack, HAlign::Center,
             VAlign::Top);
  if (!y_label.empty())
    put_text_vertical(img, y_label, {cvRound(left) - max_w - 24, cvRound((top + bottom) / 2)}, kLabelFont, kBlack);
}

void colour_bar(cv::Mat& img, int left, int top, int w, int bottom, double lo, double hi, const std::string& label,
                cv::Scalar (*colour_of)(double)) {
  const int h = bottom - top;
  for (int r = 0; r < h; ++r) {  // O(h) rows
    const double t = h > 1 ? static_cast<double>(h - 1 - r) / (h - 1) : 0.5;
    cv::rectangle(img, cv::Point(left, top + r), cv::Point(left + w - 1, top + r), colour_of(t), cv::FILLED);
  }
  cv::rectangle(img, cv::Point(left - 1, top - 1), cv::Point(left + w, bottom), kAxisGrey, 1);
  if (!(hi > lo)) {
    put_text(img, compact_number(lo, 4), {left + w + 9, (top + bottom) / 2}, kTickFont, kTextGrey, HAlign::Left,
             VAlign::Middle);
    put_text_vertical(img, label, {left + w + 80, (top + bottom) / 2}, kLabelFont, kBlack);
    return;
  }
  const double step = nice_step(lo, hi, 6);
  int max_w = 0;
  for (double v : nice_ticks(lo, hi, 6)) {
    const double py = bottom - 0.5 - (v - lo) / (hi - lo) * (h - 1);
    line(img, {static_cast<double>(left + w), py}, {static_cast<double>(left + w + 5), py}, kAxisGrey, 1);
    const std::string s = tick_label(v, step);
    put_text(img, s, {left + w + 9, cvRound(py)}, kTickFont, kTextGrey, HAlign::Left, VAlign::Middle);
    max_w = std::max(max_w, text_size(s, kTickFont).width);
  }
  put_text_vertical(img, label, {left + w + 9 + max_w + 18, (top + bottom) / 2}, kLabelFont, kBlack);
}

int legend(cv::Mat* img, const std::vector<LegendItem>& items, int left, int top, int width) {
  constexpr int kRow = 24, kSample = 30, kGapAfterSample = 7, kGapBetween = 26;
  int x = left, y = top;
  for (const auto& it : items) {  // O(items)
    const int w = kSample + kGapAfterSample + text_size(it.name, kLabelFont).width;
    if (x > left && x + w > left + width) {
      x = left;
      y += kRow;
    }
    if (img) {
      const double cy = y + kRow / 2.0;
      const cv::Point2d a(x + 2, cy), b(x + kSample - 2, cy), mid(x + kSample / 2.0, cy);
      switch (it.kind) {
        case LegendKind::Line: line(*img, a, b, it.colour, 3); break;
        case LegendKind::Dashed: dashed_polyline(*img, {a, b}, it.colour, 2, 6, 4); break;
        case LegendKind::Box:
          cv::rectangle(*img, cv::Point(x + 4, y + 5), cv::Point(x + kSample - 4, y + kRow - 5), it.colour, cv::FILLED);
          cv::rectangle(*img, cv::Point(x + 4, y + 5), cv::Point(x + kSample - 4, y + kRow - 5), kAxisGrey, 1);
          break;
        case LegendKind::Dot: circle_at(*img, mid, 3.5, it.colour, -1); break;
        case LegendKind::CircledCross:
          circle_at(*img, mid, 7.0, it.colour, 2);
          line(*img, mid + cv::Point2d(-5, -5), mid + cv::Point2d(5, 5), it.colour, 2);
          line(*img, mid + cv::Point2d(-5, 5), mid + cv::Point2d(5, -5), it.colour, 2);
          break;
      }
      put_text(*img, it.name, {x + kSample + kGapAfterSample, y + kRow / 2}, kLabelFont, kBlack, HAlign::Left,
               VAlign::Middle);
    }
    x += w + kGapBetween;
  }
  return items.empty() ? 0 : y + kRow - top;
}

namespace {
constexpr int kTitleLine = 32, kTitleTop = 14;
}

int title_height(const std::string& text) {
  const auto lines = wrap(text, kTitleFont, kWidth - 60);
  return kTitleTop + static_cast<int>(lines.size()) * kTitleLine + 8;
}

int title(cv::Mat& img, const std::string& text) {
  const auto lines = wrap(text, kTitleFont, img.cols - 60);
  int y = kTitleTop;
  for (const auto& l : lines) {
    put_text(img, l, {img.cols / 2, y}, kTitleFont, kBlack, HAlign::Center, VAlign::Top);
    y += kTitleLine;
  }
  return y + 8;
}

void write_png(const std::filesystem::path& path, const cv::Mat& img) {
  std::vector<unsigned char> buf;
  // A fixed compression level and strategy: zlib output is then a pure function of the pixels.
  const std::vector<int> params = {cv::IMWRITE_PNG_COMPRESSION, 6, cv::IMWRITE_PNG_STRATEGY,
                                   cv::IMWRITE_PNG_STRATEGY_DEFAULT};
  bool ok = false;
  try {
    ok = cv::imencode(".png", img, buf, params);
  } catch (const cv::Exception& e) {
    fail(path, std::string("PNG encoding failed: ") + e.what());
  }
  if (!ok || buf.empty()) fail(path, "PNG encoding failed");
  try {
    write_file_atomic(path, buf);
  } catch (const Error& e) {  // name the picture itself, not only the folder that failed
    fail(path, std::string("cannot write PNG: ") + e.what());
  }
}

void fail(const std::filesystem::path& path, const std::string& what) { throw file_error(path.string(), what); }

Layout make_layout(const cv::Mat& img, const Axis& x, const Axis& y) {
  Layout l;
  l.width = img.cols;
  l.height = img.rows;
  l.plot_left = cvRound(x.p0);
  l.plot_right = cvRound(x.p1);
  l.plot_bottom = cvRound(y.p0);
  l.plot_top = cvRound(y.p1);
  l.x_min = x.lo;
  l.x_max = x.hi;
  l.y_min = y.lo;
  l.y_max = y.hi;
  l.log_x = x.log;
  l.log_y = y.log;
  return l;
}

}  // namespace detail
}  // namespace millnet::report
