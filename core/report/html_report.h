// The pieces of the self-contained HTML report (mpumesh run --html, mpumesh report): SVG
// charts drawn here (histograms, a scatter plot, a bar chart), images embedded as base64
// data URIs, and the page with a script that checks, when a browser opens it, that every
// image decoded and every chart is there (its verdict in <body data-check="...">, which
// the browser test reads). Nothing is fetched when the page is viewed.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace mpumesh::report {

std::string base64(const std::string& bytes);
std::string escape_html(const std::string& s);

struct Series {
  std::string name, colour;  // colour: CSS, e.g. "#1f77b4"
  std::vector<double> values;
};

// Each series' values binned over [lo, hi] (outside values clamped to the end bins), drawn
// as step lines in % of the series' count.
std::string svg_histogram(const std::string& title, const std::string& x_label, const std::vector<Series>& series,
                          double lo, double hi, int bins);

// Points (x, y); x on a log10 axis when log_x (x <= 0 left out).
std::string svg_scatter(const std::string& title, const std::string& x_label, const std::string& y_label,
                        const std::vector<double>& x, const std::vector<double>& y, bool log_x);

// Horizontal bars with their values printed (unit appended).
std::string svg_bars(const std::string& title, const std::vector<std::pair<std::string, double>>& bars,
                     const std::string& unit);

// The page, built in order.
class HtmlPage {
 public:
  explicit HtmlPage(std::string title);
  void heading(const std::string& text, int level = 2);
  void paragraph(const std::string& html);  // already escaped
  void table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows);
  struct Figure {
    std::string png;      // bytes
    std::string caption;  // plain text
  };
  void figures(const std::vector<Figure>& row);  // side by side
  void svg(const std::string& svg);
  void pre(const std::string& text);
  std::string html() const;

 private:
  std::string title_, body_;
};

}  // namespace mpumesh::report
