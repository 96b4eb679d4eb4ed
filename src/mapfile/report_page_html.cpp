// The report page's HTML: the tables and pictures are plain HTML (they show
// even where scripts are off or WebGL is missing); the 3D view is drawn by
// the embedded report.js from the JSON data block.
#include <algorithm>
#include <array>
#include <cstdio>
#include <map>

#include "report_page_parts.hpp"
#include "stridemap/mapfile/report_page.hpp"

namespace stridemap::io::detail {
namespace {

using nlohmann::json;

std::string escape_html(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

// Text inside <script> ends at the first "</script"; "<\/" means the same in
// JavaScript strings, regular expressions and JSON, and never occurs outside
// them in code.
std::string script_safe(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t k = 0; k < text.size(); ++k) {
    if (text[k] == '<' && k + 1 < text.size() && text[k + 1] == '/') {
      out += "<\\/";
      ++k;
    } else {
      out += text[k];
    }
  }
  return out;
}

std::string cell_text(const json& value) {
  if (value.is_string()) return value.get<std::string>();
  if (value.is_number_float()) {
    char text[48];
    std::snprintf(text, sizeof text, "%.6g", value.get<double>());
    return text;
  }
  return value.dump();
}

// Nested objects become "a.b" keys, so every table is two columns.
void flatten(const json& value, const std::string& prefix, std::vector<std::pair<std::string, json>>& rows) {
  if (value.is_object()) {
    for (const auto& [key, item] : value.items()) flatten(item, prefix.empty() ? key : prefix + "." + key, rows);
  } else {
    rows.emplace_back(prefix, value);
  }
}

bool array_of_objects(const json& value) {
  if (!value.is_array() || value.empty()) return false;
  for (const json& item : value)
    if (!item.is_object()) return false;
  return true;
}

std::string key_value_table(const std::string& caption, const std::vector<std::pair<std::string, json>>& rows) {
  std::string html = "<table class=\"kv\"><caption>" + escape_html(caption) + "</caption>\n";
  for (const auto& [key, value] : rows) {
    html += "<tr><th>" + escape_html(key) + "</th><td>" + escape_html(cell_text(value)) + "</td></tr>\n";
  }
  return html + "</table>\n";
}

std::string column_table(const std::string& caption, const json& items) {
  std::vector<std::string> columns;
  std::vector<std::vector<std::pair<std::string, json>>> rows;
  for (const json& item : items) {
    rows.emplace_back();
    flatten(item, "", rows.back());
    for (const auto& [key, value] : rows.back())
      if (std::find(columns.begin(), columns.end(), key) == columns.end()) columns.push_back(key);
  }
  std::string html = "<table class=\"grid\"><caption>" + escape_html(caption) + "</caption>\n<tr>";
  for (const std::string& column : columns) html += "<th>" + escape_html(column) + "</th>";
  html += "</tr>\n";
  for (const auto& row : rows) {
    html += "<tr>";
    for (const std::string& column : columns) {
      const auto at = std::find_if(row.begin(), row.end(), [&](const auto& cell) { return cell.first == column; });
      html += "<td>" + (at == row.end() ? std::string() : escape_html(cell_text(at->second))) + "</td>";
    }
    html += "</tr>\n";
  }
  return html + "</table>\n";
}

std::string summary_tables(const json& summary) {
  if (!summary.is_object()) return "<p class=\"note\">No summary.json in this folder.</p>\n";
  std::vector<std::pair<std::string, json>> run;
  std::string html;
  std::string sections;
  for (const auto& [key, value] : summary.items()) {
    if (value.is_object()) {
      std::vector<std::pair<std::string, json>> rows;
      flatten(value, "", rows);
      sections += key_value_table(key, rows);
    } else if (array_of_objects(value)) {
      sections += column_table(key, value);
    } else {
      run.emplace_back(key, value);
    }
  }
  if (!run.empty()) html += key_value_table("run", run);
  return html + sections;
}

// How to read each picture the commands write, in one line (docs/outputs.md
// has the same lines).
std::string reading_hint(const std::string& file) {
  static const std::map<std::string, std::string> hints = {
      {"elevation", "Map seen from above, +x up, +y left; colour = height (robust 2-98 % range); checker = unknown; hatched = filled by eq. 11; red line = path, green dot = start, arrow = heading at the end."},
      {"certainty", "How often each cell was confirmed (eq. 9), 0 to the cap; dark = seen little, checker = never seen."},
      {"error", "Map minus truth in the swept area: white = right, red = too high, blue = too low; symmetric range about zero."},
      {"truth", "The simulated ground truth (highest point per cell), same colours as the elevation map."},
      {"view3d", "The map as a surface seen from behind the start; colour bar = height, holes = unknown cells, scale bar and axes in the corner."},
      {"truth_view3d", "The truth over the same cells and colours, to compare with view3d.png."},
      {"unobserved", "Share of the ground ahead never observed, per mount height (y) and pitch (x): lower is better; the framed cell is the best mount."},
      {"uncertainty", "Mean predicted height uncertainty per mount: lower is better; framed = best mount."},
      {"stripe_width", "Width of ground the scan covers per mount: wider sees more per step."},
      {"look_ahead", "How far ahead of the robot the scan meets the ground, per mount."},
      {"range_share", "Share of ranges in the sensor's accurate band, per mount: higher is better."},
      {"score", "The mount score defined under the plot; higher is better; framed = best mount."},
  };
  std::string stem = file.substr(0, file.rfind('.'));
  const bool local = stem.rfind("local_", 0) == 0;
  if (local) stem = stem.substr(6);
  const auto at = hints.find(stem);
  if (at == hints.end()) return "";
  return (local ? "The final local map (robot-centred window): " : "") + at->second;
}

}  // namespace

std::string base64(std::string_view bytes) {
  static constexpr char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t k = 0;
  for (; k + 2 < bytes.size(); k += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[k]) << 16) | (static_cast<unsigned char>(bytes[k + 1]) << 8) |
                       static_cast<unsigned char>(bytes[k + 2]);
    out += kDigits[(v >> 18) & 63];
    out += kDigits[(v >> 12) & 63];
    out += kDigits[(v >> 6) & 63];
    out += kDigits[v & 63];
  }
  if (k < bytes.size()) {
    const bool two = k + 1 < bytes.size();
    const unsigned v = (static_cast<unsigned char>(bytes[k]) << 16) | (two ? static_cast<unsigned char>(bytes[k + 1]) << 8 : 0u);
    out += kDigits[(v >> 18) & 63];
    out += kDigits[(v >> 12) & 63];
    out += two ? kDigits[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string assemble_report_html(const ReportParts& parts) {
  std::string html = kReportPageMarker;
  html += "\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>" + escape_html(parts.title) + "</title>\n<style>\n";
  html += parts.style_css;
  html += "</style></head>\n<body>\n<h1>" + escape_html(parts.title) + "</h1>\n";
  html += "<p class=\"note\">Made by stridemap from the files of one run; everything is in this page and it works "
          "offline. Simulator results are labelled as such in the run's summary.</p>\n";
  html += "<section id=\"view\"><h2>The map in 3D</h2>\n"
          "<div id=\"controls\"></div>\n"
          "<div id=\"stage\"><canvas id=\"canvas3d\"></canvas><div id=\"legend\"></div></div>\n"
          "<p id=\"view-message\" class=\"message\" role=\"alert\">The 3D view needs JavaScript and WebGL.</p>\n"
          "<p class=\"help\">Drag to turn, right-drag or shift-drag to move, wheel to zoom. Holes are cells never "
          "measured. Heights can be exaggerated for relief.</p></section>\n";
  html += "<section id=\"tables\"><h2>Summary</h2>\n" + summary_tables(parts.summary) + "</section>\n";
  html += "<section id=\"pictures\"><h2>Pictures</h2>\n";
  if (parts.pictures.empty()) html += "<p class=\"note\">No PNG pictures in this folder.</p>\n";
  for (const ReportPicture& picture : parts.pictures) {
    html += "<figure><img alt=\"" + escape_html(picture.file_name) + "\" src=\"data:image/png;base64," +
            base64(picture.png_bytes) + "\"><figcaption><b>" + escape_html(picture.file_name) + "</b> " +
            escape_html(reading_hint(picture.file_name)) + "</figcaption></figure>\n";
  }
  html += "</section>\n";
  html += "<script type=\"application/json\" id=\"stridemap-data\">" + script_safe(parts.data.dump()) + "</script>\n";
  html += "<script type=\"text/plain\" id=\"three-module\">" + script_safe(parts.three_js) + "</script>\n";
  html += "<script type=\"text/plain\" id=\"orbit-module\">" + script_safe(parts.orbit_js) + "</script>\n";
  html += "<script type=\"module\">\n" + script_safe(parts.script_js) + "</script>\n</body></html>\n";
  return html;
}

}  // namespace stridemap::io::detail
