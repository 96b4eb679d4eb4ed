// Map files (mapfile/map_file.hpp) from outside: anything decodes to a map or an
// InputError. The input is tried as it is and with its trailing checksum
// made right, so that the fuzzer also reaches the checks behind the CRC.
// A map that decodes encodes to bytes that decode to the very same map.
#include <zlib.h>

#include <cstring>
#include <string>

#include "fuzz_target.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/mapfile/map_file.hpp"

namespace {

void decode_and_check(const std::string& bytes) {
  using namespace stridemap;
  try {
    const io::MapFile file = io::decode_map_file(bytes, "fuzz.smap");
    const std::string again = io::encode_map_file(file.map, file.metadata);
    const io::MapFile reloaded = io::decode_map_file(again, "re-encoded.smap");
    fuzz::check(io::encode_map_file(reloaded.map, reloaded.metadata) == again,
                "a decoded map does not survive encode and decode unchanged");
  } catch (const InputError&) {
  }
}

}  // namespace

STRIDEMAP_FUZZ_TARGET(map_file) {
  std::string bytes(stridemap::fuzz::as_text(data));
  decode_and_check(bytes);
  if (bytes.size() < 4) return;
  const auto crc = static_cast<std::uint32_t>(
      crc32(0L, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(bytes.size() - 4)));
  for (std::size_t k = 0; k < 4; ++k) bytes[bytes.size() - 4 + k] = static_cast<char>((crc >> (8 * k)) & 0xFF);
  decode_and_check(bytes);
}
