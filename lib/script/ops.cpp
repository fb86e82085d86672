#include "script/ops.h"

#include <stdexcept>

namespace ffd {

const std::vector<Op>& op_table() {
  static const std::vector<Op> table = {
      {"lattice", check_lattice, run_lattice},
      {"move", check_move, run_move},
      {"drag", check_drag, run_drag},
      {"remesh", check_remesh, run_remesh},
      {"save", check_save, run_save},
      {"bcm", check_bcm, run_bcm},
      {"transform", check_transform, run_transform},
  };
  return table;
}

const Op& find_op(const std::string& name) {
  for (const Op& op : op_table())
    if (name == op.name) return op;
  throw std::logic_error("op '" + name + "' is in the schema but not in the op table");
}

}  // namespace ffd
