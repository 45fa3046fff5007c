#pragma once
// Bullet contacts -> dents of plastic bodies (source 000 §3.5): a contact whose relative
// normal speed before the step exceeds the body's plastic threshold pushes the touched
// primitive in by that speed × the step.
#include <shatter/bullet_ext/ContactSnapshot.h>
#include <shatter/bullet_ext/VisualBody.h>

#include <vector>

namespace shatter {

// Dents on `body` from this step's contacts, offsets in mesh coordinates. The approach speed
// is read from the bodies' motion before the step: Bullet's contact solve has already stopped
// them when Shatter runs. With `points`, also where each dent's contact is (mesh coordinates;
// a subdivision re-assigns the dent to the piece there).
std::vector<oriented::Dent> findDents(const ContactSnapshot& contacts, const VisualBody& body, double dt,
                                      std::vector<Eigen::Vector3d>* points = nullptr);

} // namespace shatter
