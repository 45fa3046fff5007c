#pragma once
// Shatter's record of the worlds a Plugin is attached to, by their dispatcher, and whether each
// takes its contacts in the own order (OrderedContacts.h, HullPairContacts::contactOrder).
//
// Per dispatcher, because what a Plugin puts in a world lives there: the group shape's
// collision algorithms, and the order its solver, the Plugin's contact snapshot and the group
// algorithms (which then free empty leaf manifolds) must agree on. So one Plugin per
// dispatcher: a second would share the algorithms and the order, and undo them under the first
// when it detaches. The record is Shatter's own, not a bit of Bullet's dispatcher flags, which
// an application may set outright (Bullet's samples do) and so clear without knowing.
//
// The Plugin's constructor and detach write it, between steps; any thread stepping any world
// reads it (a multi-threaded dispatcher runs the group algorithms on several), without a lock.
class btDispatcher;

namespace shatter {

// One Plugin's claim on its world's dispatcher, from the Plugin's making to its detach.
class AttachedWorld {
public:
    // Throws shatter::InputError if the dispatcher is claimed already (another Plugin on this
    // world, or on another world that shares the dispatcher). Contacts in Bullet's order.
    explicit AttachedWorld(const btDispatcher& dispatcher);
    ~AttachedWorld(); // the claim ends: a later Plugin may attach, in Bullet's order until it says otherwise
    AttachedWorld(const AttachedWorld&) = delete;
    AttachedWorld& operator=(const AttachedWorld&) = delete;

    void setContactsOrdered(bool ordered);
    bool contactsOrdered() const;

    struct Entry; // in the record's list

private:
    Entry* entry_;
};

// Whether the world of this dispatcher takes its contacts in the own order (false for null or
// a dispatcher no Plugin claims): what the solver wrapper, the contact snapshot and the group
// algorithms ask.
bool dispatcherOrdersContacts(const btDispatcher* dispatcher);

} // namespace shatter
