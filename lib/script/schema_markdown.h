// The script reference in Markdown (`ffdtool schema --markdown`, checked in as
// docs/script-reference.md): every op and key from the op tables, and the shared types.
#pragma once

#include <string>

namespace ffd {

/// The whole reference, generated from the op tables and the schema's grammar.
std::string script_reference_markdown();

}  // namespace ffd
