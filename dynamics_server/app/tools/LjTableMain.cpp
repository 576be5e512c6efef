// bop-lj-table: writes the volume potential (paper eq. 1 with a cutoff treatment) as a LAMMPS
// `pair_style table` file, so LAMMPS runs exactly our pair potential in benchmarks.
#include "core/Potentials.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <fstream>
#include <iostream>

int main(int argc, char** argv) {
    CLI::App app{"bop-lj-table: write BoP's LJ-form potential as a LAMMPS pair_style table file"};
    std::string out, mode = "switched";
    double rOn = 1.2, rCut = 1.6, rMin = 0.6;
    int points = 20000;
    app.add_option("output", out, "table file to write")->required();
    app.add_option("--mode", mode, "switched or paper (truncated)")->check(CLI::IsMember({"switched", "paper"}));
    app.add_option("--switch-r0", rOn, "switch start, multiples of r0 (switched mode)");
    app.add_option("--cutoff-r0", rCut, "cutoff, multiples of r0");
    app.add_option("--rmin", rMin, "first table distance, simulation length units");
    app.add_option("--points", points, "table points");
    CLI11_PARSE(app, argc, argv);
    bop::core::LjParams p;
    p.mode = mode == "switched" ? bop::core::LjCutoff::Switched : bop::core::LjCutoff::Truncated;
    p.rOnR0 = rOn;
    p.rCutR0 = rCut;
    const bop::core::LjForm lj(p);
    // LAMMPS aborts on "Pair distance > table outer cutoff": extend the table slightly past rc.
    const double rMax = lj.cutoff() * 1.001;
    std::ofstream f(out);
    if (!f) {
        std::cerr << "bop-lj-table: error: cannot write " << out << "\n";
        return 2;
    }
    f << "# BoP LJ-form potential 1.5 (r^-3 - r^-1), " << mode << ", cutoff " << rCut << " r0\n\nLJ\nN " << points
      << " R " << rMin << " " << rMax << "\n\n";
    char line[160];
    for (int i = 0; i < points; ++i) {
        const double r = rMin + (rMax - rMin) * i / (points - 1);
        const bool in = r < lj.cutoff();
        std::snprintf(line, sizeof line, "%d %.10f %.12e %.12e\n", i + 1, r, in ? lj.energy(r) : 0.0,
                      in ? lj.force(r) : 0.0);
        f << line;
    }
    std::cout << "wrote " << out << ": " << points << " points, r in [" << rMin << ", " << rMax << "], cutoff "
              << lj.cutoff() << "\n";
    return 0;
}
