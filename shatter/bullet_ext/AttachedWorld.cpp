#include <shatter/bullet_ext/AttachedWorld.h>

#include <shatter/plugin/common/InputError.h>

#include <atomic>
#include <mutex>

namespace shatter {

// An entry of the record, never freed: a reader walking the list while a Plugin detaches
// elsewhere can never meet freed memory, and a later claim reuses the entry.
struct AttachedWorld::Entry {
    std::atomic<const btDispatcher*> dispatcher{nullptr}; // null: free
    std::atomic<bool> ordered{false};
    Entry* next = nullptr; // set before the entry is published, never changed
};

namespace {

std::atomic<AttachedWorld::Entry*> head{nullptr};
std::mutex writers; // claims and their ends; readers take no lock

} // namespace

AttachedWorld::AttachedWorld(const btDispatcher& dispatcher) {
    const std::lock_guard lock(writers);
    Entry* free = nullptr;
    for (Entry* e = head.load(); e; e = e->next) {
        const btDispatcher* claimed = e->dispatcher.load();
        if (claimed == &dispatcher)
            throw InputError("shatter::Plugin: this world already has a shatter::Plugin attached (one per world and "
                             "per dispatcher: detach or destroy the other first)");
        if (!claimed && !free) free = e;
    }
    if (!free) {
        free = new Entry;
        free->next = head.load();
        head.store(free, std::memory_order_release);
    }
    free->ordered.store(false);
    free->dispatcher.store(&dispatcher);
    entry_ = free;
}

AttachedWorld::~AttachedWorld() {
    const std::lock_guard lock(writers);
    entry_->ordered.store(false);
    entry_->dispatcher.store(nullptr);
}

void AttachedWorld::setContactsOrdered(bool ordered) { entry_->ordered.store(ordered); }

bool AttachedWorld::contactsOrdered() const { return entry_->ordered.load(); }

bool dispatcherOrdersContacts(const btDispatcher* dispatcher) {
    if (!dispatcher) return false;
    for (const AttachedWorld::Entry* e = head.load(std::memory_order_acquire); e; e = e->next)
        if (e->dispatcher.load(std::memory_order_relaxed) == dispatcher) return e->ordered.load(std::memory_order_relaxed);
    return false;
}

} // namespace shatter
