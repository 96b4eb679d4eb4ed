#pragma once
// The pieces of the report page and how they are put together
// (report_page_html.cpp); report_page.cpp gathers them from a run's folder.
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace stridemap::io::detail {

struct ReportPicture {
  std::string file_name;
  std::string png_bytes;
};

struct ReportParts {
  std::string title;
  std::string three_js, orbit_js, script_js, style_css;
  nlohmann::json summary;  ///< summary.json, or null
  std::string printed_table;  ///< table.txt: the table the command printed, or empty
  bool path_drawn = false;    ///< path.csv is there: the run drew its path on its map pictures
  std::vector<ReportPicture> pictures;
  nlohmann::json data;     ///< the maps and messages the page's script reads
};

std::string base64(std::string_view bytes);
std::string assemble_report_html(const ReportParts& parts);
/// How to read a picture the commands write, from its file name; never empty.
std::string picture_caption(const std::string& file_name, bool path_drawn);

}  // namespace stridemap::io::detail
