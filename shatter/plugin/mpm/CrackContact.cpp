#include <shatter/plugin/mpm/CrackContact.h>

namespace shatter::mpm {

bool crackFieldPair(const Grid& g, size_t node, int& above, int& below) {
    if (g.fields < 3) return false;
    const bool has0 = g.node[0][node].mass > 0, has1 = g.node[1][node].mass > 0, has2 = g.node[2][node].mass > 0;
    if (has1 && has2) above = 1, below = 2;
    else if (has1 && has0) above = 1, below = 0;
    else if (has2 && has0) above = 0, below = 2;
    else return false;
    return true;
}

void crackContactAtNode(Grid& g, size_t i) {
    int a = 0, b = 0;
    if (!crackFieldPair(g, i, a, b)) return;
    const double normalLength = g.crackNormal[i].norm();
    if (normalLength <= 0) return;
    const Vec2 normal = g.crackNormal[i] / normalLength;
    Vec2& va = g.node[a][i].momentum;
    Vec2& vb = g.node[b][i].momentum;
    if ((va - vb).dot(normal) >= 0) return; // separating
    const double ma = g.node[a][i].mass, mb = g.node[b][i].mass;
    const Vec2 gap = g.displacement[a][i] / ma - g.displacement[b][i] / mb;
    if (gap.dot(normal) >= 0) return; // still open
    const Vec2 centre = (ma * va + mb * vb) / (ma + mb);
    va -= normal * (va - centre).dot(normal);
    vb -= normal * (vb - centre).dot(normal);
}

} // namespace shatter::mpm
