#include "args.hpp"
#include "commands.hpp"
namespace lom::cli {
int runSegment(const Words&) { throw UsageError("placeholder: being written"); }
}
