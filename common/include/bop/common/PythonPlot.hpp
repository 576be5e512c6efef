#pragma once
// Plots drawn by matplotlib (python/bop/plots.py) from the CSV files a tool has just written:
// axes with ticks, values, units and a legend, as users' own tools would draw them. The tool
// runs `python3 plots.py KIND FILES...` and waits for it. Python is $BOP_PYTHON, else
// /usr/bin/python3 (Debian's, which has python3-matplotlib), else python3 on the PATH; the script
// is $BOP_PYTHON_DIR/bop/plots.py, else the one in this source tree.
#include <string>
#include <vector>

namespace bop {

// Runs plots.py KIND FILES... (the last file is the PNG it writes). Returns "" when the plot was
// drawn, else why not (Python or matplotlib missing, a bad CSV: plots.py's own message is on
// stderr). Never throws: a missing picture must not lose the CSV files already written.
std::string plotWithMatplotlib(const std::string& kind, const std::vector<std::string>& files);

// The same plot drawn by a process of its own session that nobody waits for, its output to
// /dev/null: for an MPI rank that has a signal to obey (mpirun kills a job's ranks about a
// second after forwarding SIGINT, and Python with matplotlib takes longer to start). The PNG
// appears a second or two later. Returns the command, for the log (rerun it to see errors).
std::string plotWithMatplotlibDetached(const std::string& kind, const std::vector<std::string>& files);

}  // namespace bop
