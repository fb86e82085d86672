// The op registry: op_list.h's lines, declared and listed.
#include "script/op.h"

namespace ffd {

#define FFD_OP(function) const OpInfo& function();
#include "script/op_list.h"
#undef FFD_OP

const std::vector<const OpInfo*>& op_table() {
  static const std::vector<const OpInfo*> table = {
#define FFD_OP(function) &function(),
#include "script/op_list.h"
#undef FFD_OP
  };
  return table;
}

const OpInfo* find_op(const std::string& name) {
  for (const OpInfo* op : op_table())
    if (op->name() == name) return op;
  return nullptr;
}

nlohmann::json OpInfo::schema() const {
  nlohmann::json s = object_schema(keys_);
  s["title"] = name_;
  s["description"] = doc_;
  s["properties"]["op"] = {{"const", name_}};
  nlohmann::json required = nlohmann::json::array({"op"});
  for (const auto& key : s.value("required", nlohmann::json::array())) required.push_back(key);
  s["required"] = required;
  return s;
}

}  // namespace ffd
