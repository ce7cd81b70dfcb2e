// `hairtrace fiber eval|sample|furnace|afs`: query the fibre scattering models from the command line.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

namespace ht {

// args: the words after `hairtrace fiber` (a leading "fiber" is skipped).  Exit codes: 0 ok,
// 2 bad input (usage, a bad JSON line: that line gets {"error": ...} and the run continues),
// 3 device failure (--precision float).
int fiber_main(const std::vector<std::string>& args);
int fiber_main(const std::vector<std::string>& args, std::istream& in, std::ostream& out, std::ostream& err);

}  // namespace ht
