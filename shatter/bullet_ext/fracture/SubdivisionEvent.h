#pragma once
// The fracture event of a body whose fracture mode is Subdivide (source 000 §3.6, ductile
// fracture): the pattern placed at the hit cuts the primitives near it, the body keeps them
// all, in place, as one body (same btRigidBody), and a plastic body then dents on the finer
// primitives in the same step.
#include <shatter/bullet_ext/ContactSnapshot.h>
#include <shatter/bullet_ext/System.h>
#include <shatter/plugin/fracture/Subdivision.h>

namespace shatter {

struct SubdivisionOutcome {
    int primitivesBefore = 0, primitivesAfter = 0;
    int primitivesCut = 0; // 0: the pattern cut nothing and the body is unchanged
    int dented = 0;        // primitives the same step's dents moved
    // Wall-clock seconds: cutting (fractureMesh), re-assembly as one body, and the body's
    // rebuild (shape, particles, mass properties) with the dent.
    double cutSeconds = 0.0, assemblySeconds = 0.0, bodySeconds = 0.0;
};

// Subdivides `body` at `where` (rest coordinates) by `pattern` (fracture::subdivideMesh) and
// replaces its mesh in place (VisualBody::subdivide, inside context.reshape). With `contacts`
// and a plastic body, this step's dents (findDents) are taken before the cut and applied to
// the piece of their primitive nearest to their contact point right after it: the reshape
// drops the body's contact pairs for the rest of the step, so the deformation system, which
// runs after fracture, sees none of them. Pushes BodySubdivided (count = primitives after) and
// BodyDented. Nothing changes when the pattern cut nothing.
SubdivisionOutcome subdivideInPlace(SystemContext& context, VisualBody& body, const fracture::FracturePattern& pattern,
                                    const fracture::Placement& where, const fracture::CutSettings& cut,
                                    const ContactSnapshot* contacts, double dt);

} // namespace shatter
