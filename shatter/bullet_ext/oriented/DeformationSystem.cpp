#include <shatter/bullet_ext/oriented/DeformationSystem.h>

#include <shatter/bullet_ext/VisualBody.h>
#include <shatter/bullet_ext/oriented/PlasticDents.h>
#include <shatter/bullet_ext/oriented/SoftContacts.h>

#include <algorithm>

namespace shatter {

void DeformationSystem::add(VisualBody& body) {
    bodies_.push_back(&body);
    if (body.deformation() == Deformation::Plastic) ++plastic_;
}

void DeformationSystem::forget(VisualBody& body) {
    const auto it = std::find(bodies_.begin(), bodies_.end(), &body);
    if (it == bodies_.end()) return;
    if (body.deformation() == Deformation::Plastic) --plastic_;
    bodies_.erase(it);
}

void DeformationSystem::step(double dt, const ContactSnapshot& contacts) {
    for (VisualBody* body : bodies_) {
        if (body->deformation() == Deformation::Soft) {
            const auto touching = softContacts(context_.world(), *body);
            context_.reshape(*body, [&](CollisionFilter&) { body->advanceSoft(dt, touching); });
            continue;
        }
        const auto dents = findDents(contacts, *body, dt);
        if (dents.empty()) continue;
        oriented::PlasticResult result;
        context_.reshape(*body, [&](CollisionFilter&) { result = body->dent(dents); });
        if (!result.moved.empty()) context_.push(EventType::BodyDented, *body, int(result.moved.size()));
    }
}

} // namespace shatter
