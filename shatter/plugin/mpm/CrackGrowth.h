#pragma once
// Crack-tip analysis and growth (§3.1.8-3.1.9 of 001, extended to both tips and several
// cracks). At every substep each propagating tip gets J (JIntegral.h), K_I and K_II
// (StressIntensity.h) and the hoop-stress direction and criterion (HoopStress.h); when the
// criterion holds, a crack particle is added half a cell ahead in that direction (or at the
// next guide point).
//
// The source fought spurious kinks from numerical noise in the shearing displacement by
// rounding it to a user-chosen number of decimal places, which made the path depend on
// the units and on that number. Here the noise is filtered on physical grounds instead:
//  1. the mode split comes from the fields on the whole J contour (JIntegral.h), not from
//     one particle's displacement;
//  2. K_I and K_II are low-pass filtered in time with a time constant of one shear-wave
//     transit of the contour's diameter, 2r/c_s: a contour of radius r cannot resolve
//     faster changes, so anything faster is numerical ringing;
//  3. a mode mixity |K_II/K_I| below CrackGrowthSettings::mixityTolerance (2%, the accuracy
//     the validation measures for symmetric loads) counts as pure mode I and grows straight.
// Growth is also limited to the Rayleigh wave speed c_R, the limit of a running crack:
// a tip grows at most one step per (growth length)/(speedLimit·c_R); and a step may not
// cross or touch an existing crack (cracks do not merge here).
#include <shatter/plugin/mpm/SimulationState.h>

namespace shatter::mpm {

// J, K_I, K_II and the kink angle at every active tip that has not left the body.
void analyseAllTips(SimulationState& s);

// After a substep of length `dt`: when due (CrackGrowthSettings::analysisCells), analyses the
// propagating tips and grows those that meet the criterion.
void growCracks(SimulationState& s, double dt);

} // namespace shatter::mpm
