#pragma once
// Bullet objects of Shatter's that tell Shatter when someone else deletes them.
//
// Bullet's own samples clean up by deleting, in the world, every constraint, every collision
// object's motion state and every collision object, then the world. An application that does
// so deletes Shatter's bodies, motion states and joint constraints too. Each of them is a
// Watched<...>: its destructor tells Shatter, which lets go of it (never deleting it a second
// time) and forgets what depended on it. Shatter deletes the objects nobody else deleted.
#include <cassert>
#include <functional>
#include <memory>

namespace shatter {

class DeletionWatch {
public:
    virtual ~DeletionWatch() = default;
    // Run once, from the destructor, when someone deletes the object; Shatter clears it before
    // deleting the object itself.
    std::function<void()> onDelete;

protected:
    void notify() {
        if (!onDelete) return;
        const auto call = std::move(onDelete); // the call may destroy whoever set it
        onDelete = nullptr;
        call();
    }
};

// A Bullet type (any with a virtual destructor: btRigidBody, btCollisionObject,
// btDefaultMotionState, btHingeConstraint, ...) that notifies its DeletionWatch on deletion.
template <class BulletType>
class Watched final : public BulletType, public DeletionWatch {
public:
    using BulletType::BulletType;
    ~Watched() override { notify(); }
};

// Shatter's owning pointer to a Watched object: it deletes the object unless someone else did
// first; then it lets go and runs `deleted`. Not movable (the watch refers to it).
template <class T>
class WatchedPtr {
public:
    WatchedPtr() = default;
    ~WatchedPtr() { reset(); }
    WatchedPtr(const WatchedPtr&) = delete;
    WatchedPtr& operator=(const WatchedPtr&) = delete;

    // Takes `object`, whose dynamic type must be a Watched<...>.
    void reset(std::unique_ptr<T> object, std::function<void()> deleted = {}) {
        reset();
        watch_ = dynamic_cast<DeletionWatch*>(object.get());
        assert(watch_ && "WatchedPtr takes Watched<...> objects");
        object_ = std::move(object);
        watch_->onDelete = [this, deleted = std::move(deleted)] {
            (void)object_.release(); // being deleted by someone else
            watch_ = nullptr;
            if (deleted) deleted();
        };
    }
    // Deletes the object if it is still Shatter's.
    void reset() {
        if (watch_) watch_->onDelete = nullptr;
        watch_ = nullptr;
        object_.reset();
    }

    T* get() const { return object_.get(); }
    T& operator*() const { return *object_; }
    T* operator->() const { return object_.get(); }
    explicit operator bool() const { return bool(object_); }

private:
    std::unique_ptr<T> object_;
    DeletionWatch* watch_ = nullptr;
};

} // namespace shatter
