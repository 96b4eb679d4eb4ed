#include "stridemap/sensors/scip_reply.hpp"

#include "stridemap/sensors/scip_status.hpp"

namespace stridemap::scip {

bool succeeded(const Reply& reply) { return status_means_success(reply.echo.type, reply.status); }

bool switched_to_scip2(const Reply& reply) {
  return reply.echo.type == CommandType::switch_to_scip2 && status_means_success(reply.echo.type, reply.status);
}

const std::string* find_field(const std::vector<InfoField>& fields, std::string_view key) {
  for (const auto& field : fields) {
    if (field.key == key) return &field.value;
  }
  return nullptr;
}

}  // namespace stridemap::scip
