#include "stridemap/mapfile/report_page.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <zlib.h>

#include "live/test_folder.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/core/grid_map.hpp"
#include "stridemap/mapfile/map_file.hpp"

namespace stridemap::io {
namespace {

// Stand-ins for the build's web assets: the page only embeds them.
std::string fake_assets(const test::TestFolder& folder) {
  std::filesystem::create_directories(folder.path() / "assets");
  folder.write("assets/three.module.min.js", "export const REVISION = 'test'; // </script> inside");
  folder.write("assets/OrbitControls.js", "import { REVISION } from 'three';");
  folder.write("assets/report.js", "document.body.dataset.view = 'ready';");
  folder.write("assets/report.css", "body { color: #222; }");
  return folder / "assets";
}

void write_map(const std::string& path, int n) {
  ElevationMap map(GridOptions{n, 0.02});
  for (int s = 0; s < n * n; ++s) {
    map.elevation_data()[s] = s % 3 == 0 ? NAN : 0.001f * static_cast<float>(s);
    map.certainty_data()[s] = s % 3 == 0 ? 0.0f : static_cast<float>(1 + s % 7);
    map.state_data()[s] = s % 3 == 0 ? 0 : 1;
  }
  save_map_file(path, map, MapFileMetadata{});
}

std::string from_base64(const std::string& text) {
  const std::string digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  unsigned bits = 0;
  int count = 0;
  for (char c : text) {
    if (c == '=') break;
    bits = (bits << 6) | static_cast<unsigned>(digits.find(c));
    if ((count += 6) >= 8) out += static_cast<char>((bits >> (count -= 8)) & 0xffu);
  }
  return out;
}

std::string inflated(const std::string& packed, std::size_t size) {
  std::string out(size, '\0');
  uLongf got = size;
  EXPECT_EQ(uncompress(reinterpret_cast<Bytef*>(out.data()), &got, reinterpret_cast<const Bytef*>(packed.data()),
                       static_cast<uLong>(packed.size())), Z_OK);
  EXPECT_EQ(got, size);
  return out;
}

nlohmann::json page_data(const std::string& html) {
  const std::string open = "<script type=\"application/json\" id=\"stridemap-data\">";
  const std::size_t begin = html.find(open) + open.size();
  std::string text = html.substr(begin, html.find("</script>", begin) - begin);
  for (std::size_t at; (at = text.find("<\\/")) != std::string::npos;) text.replace(at, 3, "</");
  return nlohmann::json::parse(text);
}

TEST(ReportPage, EmbedsTheMapLayersTablesAndPictures) {
  test::TestFolder folder;
  std::filesystem::create_directories(folder.path() / "run");
  write_map(folder / "run/map.smap", 8);
  folder.write("run/summary.json", R"({"experiment": "test", "map": {"coverage": 0.5}, "sweep": [{"a": 1}, {"a": 2}]})");
  ReportPageOptions options;
  options.assets_dir = fake_assets(folder);
  const ReportPage page = write_report_page(folder / "run", folder / "run/report.html", options);
  EXPECT_TRUE(page.warnings.empty()) << page.warnings.front();
  const std::string html = folder.read("run/report.html");
  EXPECT_EQ(html.rfind(kReportPageMarker, 0), 0u);
  EXPECT_NE(html.find("<caption>map</caption>"), std::string::npos);
  EXPECT_NE(html.find("<th>coverage</th><td>0.5</td>"), std::string::npos);
  EXPECT_EQ(html.find("// </script> inside"), std::string::npos);  // the asset cannot end its script early
  const nlohmann::json data = page_data(html);
  ASSERT_EQ(data["maps"].size(), 1u);
  const nlohmann::json& map = data["maps"][0];
  EXPECT_EQ(map["rows"], 8);
  EXPECT_DOUBLE_EQ(map["cell_size_m"].get<double>(), 0.02);
  // float16, deflated (zlib), base64.
  EXPECT_EQ(map["layers"][0]["name"], "elevation");
  EXPECT_EQ(map["layers"][0]["encoding"], "f16");
  EXPECT_EQ(map["layers"][0]["compression"], "deflate");
  EXPECT_GT(map["layers"][0]["data"].get<std::string>().size(), 8u);
  const std::string halves = inflated(from_base64(map["layers"][0]["data"].get<std::string>()), 8 * 8 * 2);
  // Every third slot unknown (NaN: exponent all ones), and slot 1's 0.001 m (half 0x1419) among the rest.
  int unknown = 0;
  bool found = false;
  for (std::size_t k = 0; k < 64; ++k) {
    const unsigned half = static_cast<unsigned char>(halves[2 * k]) | (static_cast<unsigned char>(halves[2 * k + 1]) << 8);
    unknown += (half & 0x7c00u) == 0x7c00u;
    found |= half == 0x1419u;
  }
  EXPECT_EQ(unknown, 22);
  EXPECT_TRUE(found);
  bool has_certainty = false, has_pending = false;
  for (const auto& layer : map["layers"]) {
    has_certainty |= layer["name"] == "certainty" && layer["encoding"] == "f16";
    has_pending |= layer["name"] == "pending_elevation";
  }
  EXPECT_TRUE(has_certainty);
  EXPECT_FALSE(has_pending);  // one value everywhere: left out
}

// Each figure's caption text after its name, in page order.
std::vector<std::pair<std::string, std::string>> figure_captions(const std::string& html) {
  std::vector<std::pair<std::string, std::string>> out;
  for (std::size_t at = 0; (at = html.find("<figure>", at)) != std::string::npos; ++at) {
    const std::size_t end = html.find("</figure>", at);
    const std::string figure = html.substr(at, end - at);
    const std::size_t open = figure.find("<figcaption><b>");
    if (open == std::string::npos) {
      out.emplace_back(figure.substr(0, 60), "");
      continue;
    }
    const std::size_t name_end = figure.find("</b>", open);
    const std::string name = figure.substr(open + 15, name_end - open - 15);
    const std::size_t text_end = figure.find("</figcaption>", name_end);
    std::string text = figure.substr(name_end + 4, text_end - name_end - 4);
    text.erase(0, text.find_first_not_of(' '));
    out.emplace_back(name, text);
  }
  return out;
}

TEST(ReportPage, EveryPictureHasACaptionThatFitsIt) {
  test::TestFolder folder;
  std::filesystem::create_directories(folder.path() / "run");
  for (const char* name : {"elevation.png", "truth.png", "error.png", "certainty.png", "local_elevation.png", "foothold_score.png",
                           "slope_deg.png", "step_height_m.png", "truth_foothold_score.png", "image_300lx_overlay.png",
                           "someone_elses.png"}) {
    folder.write(std::string("run/") + name, "not decoded by the page's writer");
  }
  ReportPageOptions options;
  options.assets_dir = fake_assets(folder);
  // No path.csv: no picture has a path drawn, so no caption may mention one.
  const auto without_path = figure_captions(build_report_page(folder / "run", options).html);
  ASSERT_EQ(without_path.size(), 11u);
  for (const auto& [name, caption] : without_path) {
    EXPECT_GT(caption.size(), 20u) << name << ": \"" << caption << "\"";
    EXPECT_EQ(caption.find("path"), std::string::npos) << name << ": " << caption;
  }
  const auto foothold = std::find_if(without_path.begin(), without_path.end(),
                                     [](const auto& figure) { return figure.first == "foothold_score.png"; });
  ASSERT_NE(foothold, without_path.end());
  EXPECT_NE(foothold->second.find("Foothold score"), std::string::npos) << foothold->second;
  // The rocky walk's path.csv: its elevation, truth and error pictures have the track drawn.
  folder.write("run/path.csv", "# layer: path_x_m_y_m\n0,0\n0.1,0\n");
  for (const auto& [name, caption] : figure_captions(build_report_page(folder / "run", options).html)) {
    const bool drawn = name == "elevation.png" || name == "truth.png" || name == "error.png" || name == "local_elevation.png";
    EXPECT_EQ(caption.find("Red line = path") != std::string::npos, drawn) << name << ": " << caption;
  }
}

TEST(ReportPage, ShowsThePrintedTableAndFoldsTheRawSummary) {
  test::TestFolder folder;
  std::filesystem::create_directories(folder.path() / "run");
  write_map(folder / "run/map.smap", 4);
  folder.write("run/summary.json", R"({"objects": [{"cells": 3, "kind": "box", "name": "large_box"}]})");
  ReportPageOptions options;
  options.assets_dir = fake_assets(folder);
  // Without table.txt the raw tables are all there is: shown open, name first.
  std::string html = build_report_page(folder / "run", options).html;
  EXPECT_NE(html.find("<details id=\"summary-json\" open>"), std::string::npos);
  EXPECT_NE(html.find("<tr><th>name</th><th>cells</th><th>kind</th></tr>"), std::string::npos);
  EXPECT_EQ(html.find("class=\"printed\""), std::string::npos);
  folder.write("run/table.txt", "object  truth [mm]  map [mm]\nlarge_box  200.0  <n/a>\n");
  html = build_report_page(folder / "run", options).html;
  const std::size_t printed = html.find("<pre>object  truth [mm]  map [mm]\nlarge_box  200.0  &lt;n/a&gt;\n</pre>");
  EXPECT_NE(printed, std::string::npos);
  const std::size_t raw = html.find("<details id=\"summary-json\">");
  EXPECT_NE(raw, std::string::npos);
  EXPECT_LT(printed, raw);
  // A folder with only the printed table still makes a page.
  std::filesystem::create_directories(folder.path() / "table_only");
  folder.write("table_only/table.txt", "scene  seed\n");
  EXPECT_NE(build_report_page(folder / "table_only", options).html.find("<pre>scene  seed\n</pre>"), std::string::npos);
}

TEST(ReportPage, ADamagedMapStillGivesAPageThatSaysWhy) {
  test::TestFolder folder;
  std::filesystem::create_directories(folder.path() / "run");
  write_map(folder / "run/map.smap", 6);
  std::string bytes = folder.read("run/map.smap");
  bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x5a);
  folder.write("run/map.smap", bytes);
  ReportPageOptions options;
  options.assets_dir = fake_assets(folder);
  const ReportPage page = build_report_page(folder / "run", options);
  ASSERT_EQ(page.warnings.size(), 1u);
  EXPECT_NE(page.warnings[0].find("checksum"), std::string::npos) << page.warnings[0];
  const nlohmann::json data = page_data(page.html);
  EXPECT_TRUE(data["maps"].empty());
  EXPECT_NE(data["messages"][0].get<std::string>().find("checksum"), std::string::npos);
}

TEST(ReportPage, RefusesWhatIsNotARunAndNeverReplacesAUsersFile) {
  test::TestFolder folder;
  ReportPageOptions options;
  options.assets_dir = fake_assets(folder);
  std::filesystem::create_directories(folder.path() / "empty");
  EXPECT_THROW(build_report_page(folder / "empty", options), InputError);
  EXPECT_THROW(build_report_page(folder / "missing", options), InputError);
  std::filesystem::create_directories(folder.path() / "run");
  write_map(folder / "run/map.smap", 4);
  folder.write("run/mine.html", "<html>my own page</html>");
  EXPECT_THROW(write_report_page(folder / "run", folder / "run/mine.html", options), InputError);
  EXPECT_EQ(folder.read("run/mine.html"), "<html>my own page</html>");
  ReportPageOptions no_assets;
  no_assets.assets_dir = folder / "nowhere";
  try {
    build_report_page(folder / "run", no_assets);
    FAIL() << "missing assets accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("three.module.min.js"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace stridemap::io
