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

// Columns that name a row come first, so that a row is read from its name;
// the rest keep the order they first appear in.
std::vector<std::string> ordered_columns(std::vector<std::string> columns) {
  std::vector<std::string> out;
  for (const char* lead : {"name", "label", "scene", "seed"}) {
    const auto at = std::find(columns.begin(), columns.end(), lead);
    if (at == columns.end()) continue;
    out.push_back(*at);
    columns.erase(at);
  }
  out.insert(out.end(), columns.begin(), columns.end());
  return out;
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
  columns = ordered_columns(std::move(columns));
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

// A table wider than the window scrolls in its own box, not the page.
std::string boxed(const std::string& table) { return "<div class=\"scroll-box\">" + table + "</div>\n"; }

std::string summary_tables(const json& summary) {
  std::vector<std::pair<std::string, json>> run;
  std::string sections;
  for (const auto& [key, value] : summary.items()) {
    if (value.is_object()) {
      std::vector<std::pair<std::string, json>> rows;
      flatten(value, "", rows);
      sections += boxed(key_value_table(key, rows));
    } else if (array_of_objects(value)) {
      sections += boxed(column_table(key, value));
    } else {
      run.emplace_back(key, value);
    }
  }
  return "<div class=\"tables\">\n" + (run.empty() ? std::string() : boxed(key_value_table("run", run))) + sections +
         "</div>\n";
}

// The table the command printed is the readable one (names first, units in
// the headers, the tool's own rounding); summary.json's every value stays
// below it, folded, for whoever needs a key the table leaves out.
std::string summary_section(const ReportParts& parts) {
  std::string html = "<section id=\"tables\"><h2>Summary</h2>\n";
  if (!parts.printed_table.empty()) {
    html += "<div class=\"printed\"><h3>As the command printed it (table.txt)</h3>\n<div class=\"scroll-box\"><pre>" +
            escape_html(parts.printed_table) + "</pre></div></div>\n";
  }
  if (parts.summary.is_object()) {
    html += std::string("<details id=\"summary-json\"") + (parts.printed_table.empty() ? " open" : "") +
            "><summary>Every value of summary.json, by its key</summary>\n" + summary_tables(parts.summary) +
            "</details>\n";
  } else if (parts.printed_table.empty()) {
    html += "<p class=\"note\">No summary.json or table.txt in this folder.</p>\n";
  }
  return html + "</section>\n";
}

std::string path_sentence(bool path_drawn) {
  return path_drawn ? " Red line = path, green dot = start, arrow = heading at the end." : "";
}

}  // namespace

// One line per picture the commands write (docs/outputs.md has the same
// lines); the path is mentioned only where the run drew it.
std::string picture_caption(const std::string& file, bool path_drawn) {
  static const std::map<std::string, std::string> hints = {
      {"certainty", "How often each cell was confirmed (eq. 9), 0 to the cap; dark = seen little, checker = never seen."},
      {"view3d", "The map as a surface seen from behind the start; colour bar = height, holes = unknown cells, scale bar and axes in the corner."},
      {"truth_view3d", "The truth over the same cells and colours, to compare with view3d.png."},
      {"foothold_score", "Foothold score of each cell (docs/foothold.md), 0 to 1: bright = a good place for a foot; checker = unknown."},
      {"truth_foothold_score", "Foothold score of the simulated truth, 0 to 1 on the same scale: what the map's score should be."},
      {"slope_deg", "Ground slope under a foot, 0 to 45 deg (docs/foothold.md); checker = unknown."},
      {"step_height_m", "Step height within a foot's reach, 0 to 0.1 m (docs/foothold.md); checker = unknown."},
      {"unobserved", "Share of the ground ahead never observed, per mount height (x) and pitch (y): lower is better; the framed cell is the best mount."},
      {"uncertainty", "Mean predicted height uncertainty per mount: lower is better; framed = best mount."},
      {"stripe_width", "Width of ground the scan covers per mount: wider sees more per step."},
      {"look_ahead", "How far ahead of the robot the scan meets the ground, per mount."},
      {"range_share", "Share of ranges in the sensor's accurate band, per mount: higher is better."},
      {"score", "The mount score defined under the plot; higher is better; framed = best mount."},
      {"elevation_unfiltered", "One scene mapped without a filter: spikes behind edges are mixed pixels."},
      {"elevation_paper_filters", "The same scene with the paper's filters (range clustering and scan sequence), same colours."},
      {"elevation_cas", "The same scene with the CAS filter on the map, same colours."},
      {"lighting", "Stripe detections and false detections (top) and map RMS (bottom) against ambient light."},
      {"standing", "Cells still standing where an object left, scan by scan: they should fall to zero."},
      {"x_uncertainty", "Structured-light uncertainty of x_c [mm] over the light sheet, x_c across and z_c up the page; checker = not seen."},
      {"z_uncertainty", "Structured-light uncertainty of z_c [mm] over the light sheet, x_c across and z_c up the page; checker = not seen."},
  };
  std::string stem = file.substr(0, file.rfind('.'));
  const bool local = stem.rfind("local_", 0) == 0;
  if (local) stem = stem.substr(6);
  std::string hint;
  if (stem == "elevation") {
    hint = "Map seen from above, +x up, +y left; colour = height (robust 2-98 % range); checker = unknown; hatched = "
           "filled by eq. 11." + path_sentence(path_drawn);
  } else if (stem == "error") {
    hint = "Map minus truth in the swept area: white = right, red = too high, blue = too low; symmetric range about zero." +
           path_sentence(path_drawn);
  } else if (stem == "truth") {
    hint = "The simulated ground truth (highest point per cell), same colours as the elevation map." + path_sentence(path_drawn);
  } else if (const auto at = hints.find(stem); at != hints.end()) {
    hint = at->second;
  } else if (stem.rfind("image_", 0) == 0) {
    hint = stem.size() > 8 && stem.compare(stem.size() - 8, 8, "_overlay") == 0
               ? "The camera frame with the stripe found marked on it."
               : "A simulated camera frame at the light level in its name.";
  } else {
    hint = "A picture this run wrote; docs/outputs.md lists how to read each.";
  }
  return (local ? "The final local map (robot-centred window): " : "") + hint;
}

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
  html += summary_section(parts);
  html += "<section id=\"pictures\"><h2>Pictures</h2>\n";
  if (parts.pictures.empty()) html += "<p class=\"note\">No PNG pictures in this folder.</p>\n";
  html += "<div class=\"figures\">\n";
  for (const ReportPicture& picture : parts.pictures) {
    html += "<figure><img alt=\"" + escape_html(picture.file_name) + "\" src=\"data:image/png;base64," +
            base64(picture.png_bytes) + "\"><figcaption><b>" + escape_html(picture.file_name) + "</b> " +
            escape_html(picture_caption(picture.file_name, parts.path_drawn)) + "</figcaption></figure>\n";
  }
  html += "</div></section>\n";
  html += "<script type=\"application/json\" id=\"stridemap-data\">" + script_safe(parts.data.dump()) + "</script>\n";
  html += "<script type=\"text/plain\" id=\"three-module\">" + script_safe(parts.three_js) + "</script>\n";
  html += "<script type=\"text/plain\" id=\"orbit-module\">" + script_safe(parts.orbit_js) + "</script>\n";
  html += "<script type=\"module\">\n" + script_safe(parts.script_js) + "</script>\n</body></html>\n";
  return html;
}

}  // namespace stridemap::io::detail
