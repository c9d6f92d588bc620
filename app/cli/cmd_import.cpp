#include "args.hpp"
#include "commands.hpp"
namespace lom::cli {
int runImport(const Words&) { throw UsageError("placeholder: being written"); }
}
