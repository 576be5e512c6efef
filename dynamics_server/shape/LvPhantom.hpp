#pragma once
// A synthetic gated left ventricle (paper §5.2 used 8 gated PET frames; this stands in for them
// with a known answer). The endocardial cavity is a truncated prolate spheroid: an ellipsoid of
// long semi-axis a (along z) and short semi-axes b, cut by a base plane c·a above its centre.
// The apex stays put; through the cycle the cavity shortens along its axis (the base descends)
// and narrows, so that its volume follows a physiological curve: end-diastole at phase 0,
// ejection to end-systole at phase 3/8, isovolumic relaxation, rapid filling, diastasis and the
// atrial kick. Volumes in mL, lengths in mm, phase in cycles [0, 1).
#include "ScalarImage.hpp"

#include <vector>

namespace bop::shape {

struct LvPhantomParams {
    double edvMl = 120;             // end-diastolic volume, mL
    double esvMl = 50;              // end-systolic volume, mL
    int frames = 8;                 // gated frames over one cycle (frame k at phase k / frames)
    double voxelMm = 2.0;           // voxel edge, mm
    double aspectEd = 1.8;          // a / b at end-diastole
    double baseCut = 0.5;           // c: the base plane lies c·a above the ellipsoid's centre
    double axialShortening = 0.12;  // fraction of a lost from end-diastole to end-systole
    int marginVoxels = 4;           // empty voxels around the end-diastolic cavity
};

// The cavity volume over the cycle, mL (end-diastole edvMl at phase 0, end-systole esvMl at
// phase 3/8; periodic).
double lvVolumeMl(const LvPhantomParams& p, double phase);

struct LvShape {
    double a = 0, b = 0;  // semi-axes, mm
    double centreZ = 0;   // the ellipsoid's centre above the apex, mm (= a)
    double baseZ = 0;     // the base plane above the apex, mm
    double volumeMl = 0;  // exact volume of the truncated spheroid, mL
};
// The cavity of a given volume (mL).
LvShape lvShapeFor(const LvPhantomParams& p, double volumeMl);

struct LvPhantom {
    std::vector<ScalarImage> frames;       // value 1 inside the cavity, 0 outside (uint8 on disk)
    std::vector<double> phase;             // per frame, cycles
    std::vector<double> volumeMl;          // per frame, the exact (analytic) volume, mL
    std::vector<double> voxelVolumeMl;     // per frame, voxels inside times the voxel volume, mL
    double ejectionFraction() const;       // from volumeMl, fraction
    double voxelEjectionFraction() const;  // from voxelVolumeMl, fraction
};
// Every frame on one grid that holds the end-diastolic cavity plus the margin. A voxel is inside
// when its centre is. std::invalid_argument for volumes or sizes out of range.
LvPhantom makeLvPhantom(const LvPhantomParams& p);

// A typical left-ventricular pressure curve on the phantom's timeline, mmHg (for comparison
// plots, as the paper's Fig. 12): about 10 at end-diastole, a rise in isovolumic contraction,
// 120 early in ejection, about 100 at end-systole, a fall to 5 in isovolumic relaxation, slow
// filling and the atrial kick.
double lvTypicalPressureMmHg(double phase);

// Ejection fraction (EDV - ESV) / EDV of a sequence of volumes (largest and smallest).
double ejectionFraction(const std::vector<double>& volumes);

}  // namespace bop::shape
