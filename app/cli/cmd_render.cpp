#include "args.hpp"
#include "commands.hpp"
namespace lom::cli {
int runRender(const Words&) { throw UsageError("placeholder: being written"); }
}
