#include "report/html_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace mpumesh::report {
namespace {

constexpr int kW = 560, kH = 320;                          // chart size
constexpr int kL = 62, kR = 16, kT = 34, kB = 48;          // plot margins

std::string svg_open(const std::string& title, int w, int h) {
  return fmt::format(
      "<svg class=\"chart\" xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\" "
      "font-family=\"sans-serif\" font-size=\"12\"><rect width=\"{0}\" height=\"{1}\" fill=\"white\"/>"
      "<text x=\"{2}\" y=\"20\" font-size=\"14\" font-weight=\"bold\">{3}</text>",
      w, h, kL, escape_html(title));
}

// Ticks at 1, 2 or 5 times a power of ten.
std::vector<double> nice_ticks(double lo, double hi, int want) {
  std::vector<double> t;
  if (!(hi > lo)) return {lo};
  const double raw = (hi - lo) / want, mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double step = raw / mag < 1.5 ? mag : raw / mag < 3.5 ? 2 * mag : raw / mag < 7.5 ? 5 * mag : 10 * mag;
  for (double v = std::ceil(lo / step) * step; v <= hi + 1e-9 * step; v += step) t.push_back(std::abs(v) < 1e-12 * step ? 0 : v);
  return t;
}

std::string axes(double x0, double x1, double y0, double y1, const std::string& xl, const std::string& yl,
                 bool log_x) {
  const double pw = kW - kL - kR, ph = kH - kT - kB;
  std::string s = fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#444\"/>", kL,
                              kT, pw, ph);
  for (double v : nice_ticks(x0, x1, 6)) {
    const double x = kL + (v - x0) / (x1 - x0) * pw;
    const std::string label = log_x ? fmt::format("1e{:g}", v) : fmt::format("{:g}", v);
    s += fmt::format("<line x1=\"{0:.1f}\" x2=\"{0:.1f}\" y1=\"{1}\" y2=\"{2}\" stroke=\"#444\"/>"
                     "<text x=\"{0:.1f}\" y=\"{3}\" text-anchor=\"middle\">{4}</text>",
                     x, kT + ph, kT + ph + 5, kT + ph + 18, label);
  }
  for (double v : nice_ticks(y0, y1, 5)) {
    const double y = kT + ph - (v - y0) / (y1 - y0) * ph;
    s += fmt::format("<line x1=\"{0}\" x2=\"{1}\" y1=\"{2:.1f}\" y2=\"{2:.1f}\" stroke=\"#ddd\"/>"
                     "<text x=\"{3}\" y=\"{4:.1f}\" text-anchor=\"end\">{5:g}</text>",
                     kL, kL + pw, y, kL - 6, y + 4, v);
  }
  s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>", kL + pw / 2, kH - 10, escape_html(xl));
  s += fmt::format("<text transform=\"translate(14,{}) rotate(-90)\" text-anchor=\"middle\">{}</text>", kT + ph / 2,
                   escape_html(yl));
  return s;
}

}  // namespace

std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const uint32_t v = uint32_t(uint8_t(in[i])) << 16 | uint32_t(uint8_t(in[i + 1])) << 8 | uint8_t(in[i + 2]);
    out += k[v >> 18], out += k[(v >> 12) & 63], out += k[(v >> 6) & 63], out += k[v & 63];
  }
  if (i + 1 == in.size()) {
    const uint32_t v = uint32_t(uint8_t(in[i])) << 16;
    out += k[v >> 18], out += k[(v >> 12) & 63], out += "==";
  } else if (i + 2 == in.size()) {
    const uint32_t v = uint32_t(uint8_t(in[i])) << 16 | uint32_t(uint8_t(in[i + 1])) << 8;
    out += k[v >> 18], out += k[(v >> 12) & 63], out += k[(v >> 6) & 63], out += '=';
  }
  return out;
}

std::string escape_html(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      default: o += c;
    }
  }
  return o;
}

std::string svg_histogram(const std::string& title, const std::string& x_label, const std::vector<Series>& series,
                          double lo, double hi, int bins) {
  std::vector<std::vector<double>> pct(series.size(), std::vector<double>(size_t(bins), 0.0));
  double top = 1;
  for (size_t s = 0; s < series.size(); ++s) {
    for (double v : series[s].values) {
      if (!std::isfinite(v)) continue;
      const int b = std::clamp(int((v - lo) / (hi - lo) * bins), 0, bins - 1);
      pct[s][size_t(b)] += 1;
    }
    const double n = std::max<double>(1, double(series[s].values.size()));
    for (double& p : pct[s]) p = 100 * p / n, top = std::max(top, p);
  }
  top *= 1.08;
  std::string out = svg_open(title, kW, kH) + axes(lo, hi, 0, top, x_label, "% of triangles", false);
  const double pw = kW - kL - kR, ph = kH - kT - kB;
  for (size_t s = 0; s < series.size(); ++s) {
    std::string pts;
    for (int b = 0; b < bins; ++b) {
      const double y = kT + ph - pct[s][size_t(b)] / top * ph;
      pts += fmt::format("{:.1f},{:.1f} {:.1f},{:.1f} ", kL + pw * b / bins, y, kL + pw * (b + 1) / bins, y);
    }
    out += fmt::format("<polyline fill=\"none\" stroke=\"{}\" stroke-width=\"2\" points=\"{}\"/>", series[s].colour, pts);
    out += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"14\" height=\"4\" fill=\"{}\"/><text x=\"{}\" y=\"{}\">{}</text>",
                       kL + 10, kT + 12 + 16 * s, series[s].colour, kL + 30, kT + 17 + 16 * s,
                       escape_html(series[s].name));
  }
  return out + "</svg>";
}

std::string svg_scatter(const std::string& title, const std::string& x_label, const std::string& y_label,
                        const std::vector<double>& x, const std::vector<double>& y, bool log_x) {
  std::vector<std::pair<double, double>> p;
  for (size_t i = 0; i < std::min(x.size(), y.size()); ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i]) || (log_x && !(x[i] > 0))) continue;
    p.push_back({log_x ? std::log10(x[i]) : x[i], y[i]});
  }
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  if (!p.empty()) {
    x0 = x1 = p[0].first, y1 = p[0].second;
    for (auto [a, b] : p) x0 = std::min(x0, a), x1 = std::max(x1, a), y1 = std::max(y1, b);
    if (!(x1 > x0)) x1 = x0 + 1;
    y1 *= 1.05;
    if (!(y1 > y0)) y1 = 1;
  }
  std::string out = svg_open(title, kW, kH) + axes(x0, x1, y0, y1, x_label, y_label, log_x);
  const double pw = kW - kL - kR, ph = kH - kT - kB;
  for (auto [a, b] : p)
    out += fmt::format("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"1.6\" fill=\"#1f77b4\" fill-opacity=\"0.45\"/>",
                       kL + (a - x0) / (x1 - x0) * pw, kT + ph - (b - y0) / (y1 - y0) * ph);
  return out + "</svg>";
}

std::string svg_bars(const std::string& title, const std::vector<std::pair<std::string, double>>& bars,
                     const std::string& unit) {
  const int row = 22, label_w = 150, h = kT + 10 + row * int(bars.size()) + 10;
  double top = 0;
  for (const auto& b : bars) top = std::max(top, b.second);
  if (!(top > 0)) top = 1;
  std::string out = svg_open(title, kW, h);
  const double pw = kW - label_w - 90;
  for (size_t i = 0; i < bars.size(); ++i) {
    const double y = kT + 10 + row * double(i), w = std::max(1.0, bars[i].second / top * pw);
    out += fmt::format(
        "<text x=\"{}\" y=\"{:.1f}\" text-anchor=\"end\">{}</text><rect x=\"{}\" y=\"{:.1f}\" width=\"{:.1f}\" "
        "height=\"{}\" fill=\"#4c72b0\"/><text x=\"{:.1f}\" y=\"{:.1f}\">{:.3g} {}</text>",
        label_w - 8, y + 14, escape_html(bars[i].first), label_w, y + 2, w, row - 6, label_w + w + 6, y + 14,
        bars[i].second, escape_html(unit));
  }
  return out + "</svg>";
}

HtmlPage::HtmlPage(std::string title) : title_(std::move(title)) {}

void HtmlPage::heading(const std::string& text, int level) {
  body_ += fmt::format("<h{0}>{1}</h{0}>\n", level, escape_html(text));
}

void HtmlPage::paragraph(const std::string& html) { body_ += "<p>" + html + "</p>\n"; }

void HtmlPage::table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows) {
  body_ += "<table><tr>";
  for (const auto& h : header) body_ += "<th>" + escape_html(h) + "</th>";
  body_ += "</tr>\n";
  for (const auto& r : rows) {
    body_ += "<tr>";
    for (const auto& c : r) body_ += "<td>" + escape_html(c) + "</td>";
    body_ += "</tr>\n";
  }
  body_ += "</table>\n";
}

void HtmlPage::figures(const std::vector<Figure>& row) {
  body_ += "<div class=\"row\">";
  for (const auto& f : row)
    body_ += "<figure><img alt=\"" + escape_html(f.caption) + "\" src=\"data:image/png;base64," + base64(f.png) +
             "\"><figcaption>" + escape_html(f.caption) + "</figcaption></figure>";
  body_ += "</div>\n";
}

void HtmlPage::svg(const std::string& svg) { body_ += "<div class=\"svg\">" + svg + "</div>\n"; }

void HtmlPage::pre(const std::string& text) { body_ += "<pre>" + escape_html(text) + "</pre>\n"; }

std::string HtmlPage::html() const {
  // The check, once the page has loaded: every <img> decoded with a size, every chart an
  // SVG with content.
  static const char* kCheck = R"JS(
<script>
window.addEventListener('load', function () {
  const imgs = Array.from(document.images);
  const decoded = imgs.filter(im => im.complete && im.naturalWidth > 0 && im.naturalHeight > 0).length;
  const charts = Array.from(document.querySelectorAll('svg.chart'));
  const drawn = charts.filter(s => s.getBBox().width > 0 && s.childElementCount > 2).length;
  document.body.dataset.check = JSON.stringify({images: imgs.length, decoded: decoded, charts: charts.length,
                                                drawn: drawn, errors: window.reportErrors});
});
</script>
)JS";
  // Script errors and console.error calls, counted from the start.
  static const char* kErrors =
      "<script>window.reportErrors = 0; window.addEventListener('error', () => window.reportErrors++);"
      "(function () { const e = console.error; console.error = function (...a) { window.reportErrors++; "
      "e.apply(console, a); }; })();</script>\n";
  return "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" + escape_html(title_) +
         "</title>\n" + kErrors + "<style>body{font-family:sans-serif;margin:24px;max-width:1800px;color:#222}"
         "table{border-collapse:collapse;margin:8px 0}td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}"
         "th{background:#f2f2f2}.row{display:flex;flex-wrap:wrap;gap:12px}figure{margin:0}"
         "figure img{max-width:100%;border:1px solid #ddd}figcaption{font-size:13px;color:#444;max-width:600px}"
         ".svg{display:inline-block;margin:6px}pre{background:#f7f7f7;padding:8px;font-size:12px}</style></head>\n"
         "<body>\n<h1>" +
         escape_html(title_) + "</h1>\n" + body_ + kCheck + "</body></html>\n";
}

}  // namespace mpumesh::report
