#include <shatter/plugin/lattice/DamageSpreading.h>

#include <shatter/plugin/common/SettingCheck.h>

#include <cmath>
#include <sstream>

namespace shatter::lattice {

namespace {

class Spreader {
public:
    Spreader(Lattice& lattice, const DamageSpreadingSettings& s, double removalFraction, Random& random, std::vector<int>& removed)
        : lattice_(lattice), s_(s), removalFraction_(removalFraction), random_(random), removed_(removed) {}

    void run(int link) {
        const double change = s_.initialFraction * lattice_.links()[link].baseStrength;
        tau_ = s_.tauFraction * change;
        spread(link, change);
    }

private:
    void weaken(int link, double amount) {
        const Link& l = lattice_.links()[link];
        if (l.broken) return;
        lattice_.weaken(link, amount);
        if (l.strength < removalFraction_ * l.baseStrength) {
            lattice_.breakLink(link);
            removed_.push_back(link);
        }
    }

    // One call of changeConnectionStrengths for the link (n1, n2).
    void spread(int link, double change) {
        weaken(link, change);
        change *= s_.alpha;
        const int ends[2] = {lattice_.links()[link].a, lattice_.links()[link].b};
        for (int node : ends) {
            neighbours_.clear();
            for (int k : lattice_.linksOf(node))
                if (k != link && !lattice_.links()[k].broken) neighbours_.push_back(k);
            if (neighbours_.empty()) continue;
            const int selected = neighbours_[random_.below(int(neighbours_.size()))];
            weaken(selected, s_.theta * change);
            if (change < tau_) continue;
            const std::vector<int> others = neighbours_; // the recursion reuses neighbours_
            for (int k : others)
                if (k != selected) spread(k, change);
        }
    }

    Lattice& lattice_;
    const DamageSpreadingSettings& s_;
    double removalFraction_;
    Random& random_;
    std::vector<int>& removed_;
    std::vector<int> neighbours_;
    double tau_ = 0.0;
};

} // namespace

void spreadDamage(Lattice& lattice, int link, const DamageSpreadingSettings& settings, double removalFraction, Random& random,
                  std::vector<int>& removed) {
    if (!settings.enabled) return;
    Spreader(lattice, settings, removalFraction, random, removed).run(link);
}

void DamageSpreadingSettings::check(const std::string& body) const {
    requireWithin(body, "damage spreading initial fraction", initialFraction, 0.0, 1.0);
    requireSetting(alpha > 0.0 && alpha < 1.0, body, "damage spreading alpha", "in (0, 1)", alpha);
    requireSetting(theta > 1.0 && std::isfinite(theta), body, "damage spreading theta", "> 1 and finite (the source's Θ > change)", theta);
    requireSetting(tauFraction > 0.0 && tauFraction < 1.0, body, "damage spreading tau fraction", "in (0, 1)", tauFraction);
}

} // namespace shatter::lattice
