#include <shatter/bullet_ext/shape/FramedShape.h>

namespace shatter {

void FramedShape::recalculateLocalAabb() {
    btCompoundShape::recalculateLocalAabb();
    remember();
}

void FramedShape::setMargin(btScalar margin) {
    btCompoundShape::setMargin(margin);
    remember();
}

void FramedShape::remember() {
    disc_ = btCompoundShape::getAngularMotionDisc();
    rememberedAt_ = m_updateRevision;
}

} // namespace shatter
