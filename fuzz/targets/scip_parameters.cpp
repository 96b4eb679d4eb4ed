// The sensor describing itself: VV/PP/II replies. The input's lines are
// "KEY:value" fields; whatever the reply encoder accepts must decode back to
// the same fields, and the PP fields must give sensor parameters, a sensor
// model and a converted scan, or an InputError naming the field.
#include <cmath>
#include <string>
#include <vector>

#include "fuzz_target.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/sensors/scip_decoder.hpp"
#include "stridemap/sensors/scip_parameters.hpp"
#include "stridemap/sensors/scip_reply_encoder.hpp"
#include "stridemap/sensors/urg04lx.hpp"

namespace {

using namespace stridemap;
using namespace stridemap::scip;

std::vector<InfoField> fields_of(std::string_view text) {
  std::vector<InfoField> fields;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = text.substr(start, end - start);
    start = end + 1;
    const std::size_t colon = line.find(':');
    if (colon == std::string_view::npos) continue;
    fields.push_back({std::string(line.substr(0, colon)), std::string(line.substr(colon + 1))});
  }
  return fields;
}

void use_parameters(const std::vector<InfoField>& fields) {
  try {
    const ScipParameters parameters = parse_parameters(fields);
    const UrgParameters urg_parameters = to_urg_parameters(parameters);
    const UrgModel urg(urg_parameters);
    // A scan as a GD request of the whole range would bring it (the SCIP
    // command can only ask for steps 0..9999).
    if (urg_parameters.last_step > 9999) return;
    UrgRawScan raw;
    raw.first_step = urg_parameters.first_step;
    raw.values_mm.resize(static_cast<std::size_t>(urg_parameters.beam_count()));
    for (std::size_t i = 0; i < raw.values_mm.size(); ++i) raw.values_mm[i] = static_cast<std::uint32_t>(i * 37 % 6000);
    PlanarScan scan;
    const UrgConversionStats stats = urg.to_planar_scan(raw, scan);
    fuzz::check(stats.valid + stats.error_codes + stats.beyond_max_range == raw.values_mm.size(),
                "a raw value was not classified");
    for (std::size_t i = 0; i < scan.size(); ++i) {
      fuzz::check(std::isfinite(scan.angle_rad[i]) && std::isfinite(scan.range_error_m[i]),
                  "a beam's angle or range error is not finite");
    }
  } catch (const InputError&) {
  }
  try {
    (void)parse_version(fields);
  } catch (const InputError&) {
  }
}

}  // namespace

STRIDEMAP_FUZZ_TARGET(scip_parameters) {
  const std::vector<InfoField> fields = fields_of(fuzz::as_text(data));
  use_parameters(fields);
  std::string reply;
  try {
    append_info_reply("PP", fields, reply);
  } catch (const InputError&) {
    return;
  }
  const std::vector<Event> events = decode_all(reply);
  fuzz::check(events.size() == 1 && events[0].kind == EventKind::info, "an encoded PP reply does not decode as one");
  fuzz::check(events[0].info == fields, "an encoded PP reply decodes to other fields");
}
