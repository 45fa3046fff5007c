// The features of a fracture shard's hull (convexHullOf) against Bullet's
// initializePolyhedralFeatures over the same points: the same vertices, faces, planes, edge
// directions, centre and inner sphere to the bit, an inner box at least as large and inside the
// hull, and the same contacts against a box.
#include <shatter/bullet_ext/Convert.h>
#include <shatter/bullet_ext/shape/ConvexHullOfPoints.h>
#include <shatter/bullet_ext/shape/FragmentHull.h>
#include <shatter/plugin/common/InputError.h>

#include "tests/bullet_ext/shape/same_shape.h"

#include <btBulletCollisionCommon.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <memory>
#include <random>
#include <stdexcept>

namespace shatter {
namespace {

// Points of a curved shard: two layers of a cylindrical wall (radius 1 and 0.99) over `sectors`
// sectors of 8° and `rows` rows, like the corners of a vase's extruded quads cut by a cell.
// Top, bottom, side and outer faces are shared by several quads.
std::vector<Eigen::Vector3d> curvedShard(int sectors, int rows) {
    std::vector<Eigen::Vector3d> points;
    for (double r : {1.0, 0.99})
        for (int s = 0; s <= sectors; ++s)
            for (int z = 0; z <= rows; ++z) {
                const double a = 8.0 * s * M_PI / 180.0;
                points.emplace_back(r * std::cos(a), r * std::sin(a), 0.05 * z);
            }
    return points;
}

// Random points in a ball, some of them on a flat cut (z = 0.3) as crack faces have.
std::vector<Eigen::Vector3d> randomPiece(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<Eigen::Vector3d> points;
    while (points.size() < 60) {
        const double x = u(rng), y = u(rng), z = u(rng); // in this order in every compiler (not as arguments)
        Eigen::Vector3d p(x, y, z);
        if (p.norm() > 1.0) continue;
        if (p.z() > 0.3) p.z() = 0.3;
        points.push_back(0.1 * p + Eigen::Vector3d(2.0, -1.0, 0.5));
    }
    return points;
}

// Corners of a vase shard (the vase scene, seed 1, first break), body frame, m.
constexpr double kVaseShard[][3] = {
    {0.031745789661242724, 0.01127214397979495, -0.0029094754544162845},
    {0.024204636334151253, 0.015018682200070476, -0.00084844928503788905},
    {0.026234135227512466, 0.015074346732511859, -0.0014179949860102323},
    {0.027052946371621856, 0.014005410909945575, 0.0011964758541414024},
    {0.034086180849780247, 0.0026045692423018957, -0.0035962734853970642},
    {0.036415201962731902, 0.0080343052411681673, -0.0040793378960575603},
    {0.037644672455664586, 0.0072622952443778767, -0.0048404014610170824},
    {0.036873308515844215, 0.0074810637983864755, -0.0028686764515215442},
    {0.027430071791613074, 0.013513083864900974, 0.0024006404783532588},
    {0.019183733733841066, 0.013348200327152778, 0.0045551016985427668},
    {0.011728523337071434, -0.0012236422949028426, 0.0061668352492964176},
    {0.019442665276356397, -0.0050561233939101745, 0.0040585306132461139},
    {0.032224200679360125, 0.010211971478021525, 0.0010689672250662845},
    {0.026027466194924638, -0.0087400286835430489, -0.0018823804452912198},
    {0.010716993286133155, -0.0011335964320195414, 0.0023020306360428022},
    {0.018927438952831482, 0.014914417741250173, 0.00052702362170131407},
    {0.024544662676308723, 0.015026732772887406, -0.00094054787398267759},
    {0.030825911912661517, 0.011906130483774615, -0.0026572374161516997},
    {0.037210860820472015, 0.0075096208316365182, -0.004430795425656925},
    {0.036527030709425333, 0.0059153815392527327, -0.0042889615935170228},
    {0.027004140429056807, 0.014069125749120911, 0.001040638070813176},
    {0.025483017012852705, -0.0083073336973279663, -0.00010510702434943594},
    {0.03728434910321899, 0.0073644874972441567, -0.0039193594873830799},
    {0.036525318473549437, 0.0075797581687506738, -0.0019791603177911985},
    {-0.0037039361026792593, 0.014964609874905702, 0.0051296820126136133},
    {-0.0071555656109142506, 0.0092408416041599214, 0.0057793877766923255},
    {-0.0072818856948953549, 0.0088656617569955794, 0.0018030453217892446},
    {-0.002683341427970934, 0.01649133586362975, 0.00093745395126010745},
    {0.020036525163791025, 0.014886777185852617, 0.00036708622665603788},
    {-0.018805013670283678, 0.016405153422779244, 0.0019074793573998858},
    {-0.016661797450306867, 0.017148819855905405, 0.0021476625113444944},
    {-0.019143696116913612, 0.016187578357041984, -0.0022778406567169323},
    {-0.013064782900831224, 0.018296877300646875, -0.0015965969556458945},
    {-0.0015979056728773738, 0.016363991385489933, 0.0010422992779025016},
    {0.0082678898562952245, -0.0078907026329855818, 0.0065102221212299449},
    {0.014067298026701812, -0.013787670760487354, 0.0047085907531964908},
    {0.014523290847812403, -0.025606368021741013, -0.00036601400194161192},
    {0.013733946674129999, -0.025214212076422007, -0.00015028320482273088},
    {0.0035727588546042095, -0.014882088674599021, 0.0030063690334341765},
    {0.026148508362783922, -0.0085669143630756096, -0.0019043571159572585},
    {0.025556155975945179, -0.0082021051424134208, -0.00011751986375162343},
    {0.014473328243213297, -0.025575597792341326, -0.00021530127574329174},
    {0.016011581154574218, -0.021934345432130548, 0.0015023455186740978},
    {-0.01383814478288666, -0.0020380380422410339, 0.0063654667845019454},
    {-0.014072778074237532, -0.010487228731260546, 0.0027740445877328271},
    {-0.017597614635877033, -0.0085339655600083202, 0.0027017250219608505},
    {0.0044498016450224415, -0.01539115871427944, 0.0028953346548175243},
    {-0.017594562383806994, -0.0085103224653427286, 0.0031915301969610167},
    {-0.026750919165389374, 0.013639479706231547, 0.00066243461188668959},
    {-0.030189066824556212, -0.00058237269534768986, 0.002499732931239433},
    {-0.02481095610198196, -0.0038898652092996672, 0.0042872470063552775},
    {-0.032274700085376827, 0.00051967103984509216, -0.0023166616982491645},
    {-0.029802199892571872, 0.010747135444611979, -0.0036379314334834805},
    {-0.028296425554501337, 0.01300171717761139, -0.0037176615463924596},
    {-0.018888886118555704, 0.016276131222987419, -0.0022435932237085858},
    {-0.028700432211110221, 0.012885914868858145, -0.0027522845920282873},
    {-0.016777559571804979, -0.0090001008805358929, 0.0030815349335116928},
    {-0.026825820587970204, 0.013516827391652339, -0.0033526271814550523},
    {-0.030321420392157308, 0.0082828987310701093, -0.0031675366535944302},
    {-0.02959691559851256, 0.012539388150548334, -0.0043225428909778136},
    {-0.02817062394476269, 0.013090706973709962, -0.0018242854357975382},
    {0.013241076266222966, -0.024689989097406606, 1.2557588768641395e-05},
    {0.014662505992443476, -0.025396172960638383, -0.00037592461976589201},
    {0.014331636097203627, -0.025911002235440756, -0.00037351782036360173},
    {0.014566759758219437, -0.025354432779734142, -0.00011097360565562626},
    {-0.018204230768096855, -0.009570095843233312, 0.0026724684202404122},
    {-0.013142092412899074, -0.01071694878985199, 0.0027871753879600983},
    {-0.017490456745724737, -0.0083190113726686055, 0.0032845279827199408},
    {-0.031577577558514119, -0.0055678287972889288, 0.0027795970856507898},
    {-0.032208871334324714, 0.00077290073030462122, -0.0023402145840870042},
    {-0.01699766881814023, -0.0095229497436765415, 0.0028349882718613773},
    {-0.036417621833101758, -0.014338643114965329, -0.0014919111762950446},
    {-0.016680174339718794, -0.0087869366305074054, 0.0031829554476976276},
    {-0.039762633770042098, -0.017895462421459986, -0.0059709197885138539},
    {-0.034307187926566805, -0.021250515377488861, -0.0041577019721975158},
    {-0.041688916230576002, -0.023890940935214822, -0.006144012746559754},
    {-0.038818795668813758, -0.018689894604144525, -0.0036110310222567071},
    {-0.00061402359950001257, -0.023010163829838663, -0.00091681998059379391},
    {0.0014709553125078596, -0.019061203525726877, -0.00084073591576838821},
    {0.016123578512001187, -0.026340807913585135, -0.0048453541124317788},
    {0.010364554429205352, -0.035301620241141661, -0.0048032478471383838},
    {0.01447880827872652, -0.025623699949203403, -0.00029380417086622405},
    {0.014155344671211278, -0.025462999229303524, -0.00020540032460756438},
    {0.014403517306810682, -0.025740849705773179, -0.00029325369191722398},
    {0.0018433873380882487, -0.019292185608675669, 0.00094184708864696238},
    {-0.02192808236724406, -0.018181094258899733, -0.0013996813918181164},
    {-0.01662263695681241, -0.0090347677596212608, -0.0012119646203324961},
    {-0.014660260256995983, -0.010201693279080997, 0.002825027570565671},
    {-0.016719042182663898, -0.0090608338838391953, 0.0027827872605227779},
    {-0.017064799889167599, -0.0096569031350855882, 0.0027705536938078079},
    {0.0014268946516135712, -0.019073116683440611, 0.00098500959153835109},
    {-0.035028789855833471, -0.00089791700649133831, -0.0069254560412557384},
    {-0.033579429506444422, 0.0013935159394446984, -0.0068478666530821077},
    {-0.032252176725026345, 0.00046423946045181846, -0.0022381120571087214},
    {-0.036331175557596809, -0.014181990781248151, -0.0014156193163274238},
    {-0.018271346035468924, -0.0097040241084789761, 0.0026080463080973317},
    {-0.038753891119747474, -0.01857227878992114, -0.0035537504888884311},
    {-0.033805277085901718, 0.0015062928975951748, -0.0059596821823975034},
    {-0.034410868608454138, 0.0019672664492564537, -0.0074441282368112203},
    {-0.033908442540732026, 0.0015800097885510518, -0.0062096312680915578},
    {0.010670693634839351, -0.0013374044994458507, -0.0017540307125042752},
    {0.027483668336041444, -0.0096902981985142918, -0.0063490814152210601},
    {0.025978123499816881, -0.0087629836223193907, -0.0018074482651926503},
    {0.011592276658792665, -0.0016159170520257057, 0.0021242590507826839},
    {0.0043835083619805726, -0.015504003434828821, 0.0028399022947184047},
    {0.013662417020737096, -0.024938731162754017, -4.2547281049355722e-05},
    {0.014618033685975643, -0.025413493338418334, -0.0003037209858902394},
    {0.0019062750081895068, -0.019192761938242441, 0.00099121614458638567},
    {-0.0064431362878179937, 0.0081461029427076885, -0.0021051576435497646},
    {-0.0064182226463310923, 0.0083388386427540855, 0.0018861138656807769},
    {-0.013729482994453167, -0.010431447080700517, 0.0028381549674247855},
    {0.003506468688171247, -0.014994937474894707, 0.0029509353210191197},
    {0.001482662636444611, -0.018970633896401308, 0.001034827257227992},
    {-0.025163778288295337, 0.013993957816070353, -0.0072937689703302597},
    {-0.01928126051396371, 0.01604144052793027, -0.0063721444539202119},
    {-0.019197283142738296, 0.016170499247461688, -0.0022210554337532269},
    {-0.026788941228494966, 0.013528129214554391, -0.0034104540009051824},
    {-0.03039455924038274, 0.0081295713358572001, -0.0032194107429401641},
    {-0.032186346563255842, 0.00071748582744854698, -0.0022616723055437307},
    {-0.033779271613067534, 0.0015591079275728353, -0.0059401998138933782},
    {-0.032823820440515385, 0.011292060245859088, -0.0099747102141869819},
    {-0.02954053801278533, 0.012561180344405818, -0.0042237932954951657},
    {-0.029875401611835176, 0.010593669797425142, -0.0036898461825795371},
    {-0.028259555239756887, 0.013013016531878658, -0.0037754616177906445},
    {-0.033888468319067, 0.0016229818577680182, -0.0061961340069189921},
    {0.028117921815709577, -0.0088050165917514158, -0.0064944801105242134},
    {0.03568949427213032, 0.0088472391797922087, -0.008065300292102888},
    {0.037865533384561965, 0.0079015258965517126, -0.0093537952859569437},
    {0.039904022087871395, 0.006621515157934096, -0.010615647029346429},
    {0.037195844904335008, 0.0075311424782609927, -0.0044895367239655756},
    {0.03641710873788858, 0.0057156081136645652, -0.0043279778808824644},
    {0.037606970243915273, 0.0072729880677282225, -0.0047440288021697447},
    {0.036221230435138627, 0.0087081568099584665, -0.0070652104630969745},
    {0.019784865100428914, 0.016477118532303037, -0.0037248300525140597},
    {0.020310661116480614, 0.016487633636499178, -0.0038622060376956213},
    {0.031962839231988165, 0.011111271887093368, -0.0029055293810266456},
    {0.02414947501885268, 0.014993047833166502, -0.00077010688834183618},
    {0.020041154269491497, 0.014910887794992203, 0.00030328391941545073},
    {0.026099164069728054, -0.0085898749554938376, -0.0018294293126642628},
    {0.033976419262814167, 0.0024050810956187047, -0.0036352414435554719},
    {0.036400189757796811, 0.0080558249741472208, -0.0041380838360633868},
    {0.036014073112702653, 0.0088183696380545688, -0.0068252094975532031},
    {-0.000553086784847566, 0.017913388099639764, -0.0032140770554272176},
    {-0.0015737024931771558, 0.016386645595186128, 0.00097819844647643243},
    {0.018932073378736827, 0.014938524267825699, 0.00046323084119065416},
    {-0.009527013285849581, 0.019426025567464967, -0.005279186278187545},
    {-0.018942480085485172, 0.016259049591985493, -0.0021868134605659843},
    {-0.002659135762707686, 0.016513986075710946, 0.0008733630180593852},
    {-0.013124086647178467, 0.018277949351771898, -0.0015348655918622869},
    {0.035818023397707517, 0.009198172900790124, -0.008148087406243669},
    {0.036095414115889235, 0.0088583644490724117, -0.0073879393801233265},
    {0.024977577216248312, 0.016714749261270614, -0.005430195238832064},
    {0.025355567537388587, 0.015033778498485311, -0.0011285143026076138},
    {0.028666041056161239, 0.013389094323430471, -0.0020332794486557109},
    {0.02623251996277793, 0.015076455416974813, -0.0014231525398344103},
    {0.035954978910361084, 0.0089395683076905139, -0.0072617463395813148},
};

// Bullet's own features over the points (as the fracture system built them before).
btConvexPolyhedron bulletFeatures(const std::vector<Eigen::Vector3d>& points) {
    btConvexHullShape hull;
    for (const auto& p : points) hull.addPoint(toBullet(p), false);
    hull.initializePolyhedralFeatures();
    return *hull.getConvexPolyhedron();
}

// A hull shape over the features' vertices with those features.
std::unique_ptr<btConvexHullShape> hullShape(btConvexPolyhedron features) {
    auto hull = std::make_unique<btConvexHullShape>();
    for (int i = 0; i < features.m_vertices.size(); ++i) hull->addPoint(features.m_vertices[i], false);
    hull->setMargin(0.001f);
    hull->recalcLocalAabb();
    hull->setPolyhedralFeatures(features);
    return hull;
}

// The half side of the cube in the inner sphere that Bullet's search starts from, in float as
// Bullet computes it.
btScalar bulletsCube(const btConvexPolyhedron& p) { return p.m_radius / std::sqrt(btScalar(3)); }

// Every corner of the inner box behind every face by Bullet's own test, in float, unless the box
// is Bullet's starting cube (which can fail that test by rounding: Bullet keeps it then).
void expectInnerBoxInside(const btConvexPolyhedron& p) {
    const btScalar r = bulletsCube(p);
    const bool cube = p.m_extents[0] == r && p.m_extents[1] == r && p.m_extents[2] == r;
    EXPECT_TRUE(p.testContainment() || cube) << "inner box " << p.m_extents[0] << " " << p.m_extents[1] << " "
                                             << p.m_extents[2];
}

void expectBulletsFeatures(const std::vector<Eigen::Vector3d>& points) {
    const btConvexPolyhedron b = bulletFeatures(points);
    const btConvexPolyhedron f = convexHullOf(points);
    test::expectSameFeaturesButTheInnerBox(f, b);
    // The inner box: inside, at least the cube in the inner sphere, and about Bullet's (Bullet
    // steps towards the same limits, so its long side is shorter and its other sides may grow
    // further).
    expectInnerBoxInside(f);
    for (int k = 0; k < 3; ++k) {
        EXPECT_GE(f.m_extents[k], bulletsCube(f)) << k;
        EXPECT_NEAR(f.m_extents[k], b.m_extents[k], 0.01 * b.mE.length()) << k;
    }
}

TEST(ConvexHullOfPoints, RandomPiecesHaveBulletsFeatures) {
    std::mt19937 rng(7);
    for (int piece = 0; piece < 20; ++piece) {
        SCOPED_TRACE(piece);
        expectBulletsFeatures(randomPiece(rng));
    }
}

TEST(ConvexHullOfPoints, ACurvedShardHasBulletsFeatures) {
    const std::vector<Eigen::Vector3d> points = curvedShard(5, 4);
    // Outer wall: one face per sector (its rows are coplanar); chord inside; top, bottom and
    // the two side cuts: 5 + 1 + 2 + 2 = 10.
    EXPECT_EQ(convexHullOf(points).m_faces.size(), 10);
    expectBulletsFeatures(points);
}

// A vase shard (156 corners of a vase's cut quads, from the vase scene's first break at seed 1,
// shrunk by 1e-3), with sliver faces and 126 edge directions.
TEST(ConvexHullOfPoints, AVaseShardHasBulletsFeatures) {
    std::vector<Eigen::Vector3d> points;
    for (const auto& p : kVaseShard) points.emplace_back(p[0], p[1], p[2]);
    expectBulletsFeatures(points);
}

// Regular octahedra at several places and sizes: the cube in the inner sphere touches four
// faces with its corners, and no box that is longer on any side fits, so the inner box is
// Bullet's starting cube, bit for bit as Bullet's search ends. Rounded to float, that cube
// fails Bullet's own containment test for some of them (17 of the 40 here), and is kept then.
TEST(ConvexHullOfPoints, AnOctahedronsInnerBoxIsBulletsCubeEvenWhereItFailsTheFloatTest) {
    int cubes = 0, cubesOutside = 0;
    for (int i = 0; i < 40; ++i) {
        SCOPED_TRACE(i);
        const Eigen::Vector3d centre(0.37 * i, -0.21 * i, 0.05 * i);
        std::vector<Eigen::Vector3d> points;
        for (int k = 0; k < 3; ++k)
            for (double sign : {-1.0, 1.0}) points.push_back(centre + sign * (0.05 + 0.01 * i) * Eigen::Vector3d::Unit(k));
        expectBulletsFeatures(points);
        const btConvexPolyhedron f = convexHullOf(points), b = bulletFeatures(points);
        const btScalar r = bulletsCube(f);
        if (f.m_extents.x() != r || f.m_extents.y() != r || f.m_extents.z() != r) continue; // rounded up and inside
        ++cubes;
        cubesOutside += !f.testContainment();
        for (int k = 0; k < 3; ++k) EXPECT_EQ(f.m_extents[k], b.m_extents[k]) << k;
    }
    EXPECT_GE(cubes, 20);
    EXPECT_GT(cubesOutside, 0) << "a cube that fails the float test";
}

// Contacts of a box pressed into each hull at random poses: the same points, depths and
// normals (the larger inner box only lets the separating-axis test skip axes that cannot be
// the least). The box has features and the separating-axis test is on, as for the project's
// leaves, so the hull's faces, edges and inner box all take part; without them Bullet runs
// GJK on the hull's points alone, which the tests above already compare.
TEST(ConvexHullOfPoints, ContactsAgainstABoxAreBullets) {
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher(&config);
    btDbvtBroadphase broadphase;
    btCollisionWorld world(&dispatcher, &broadphase, &config);
    world.getDispatchInfo().m_enableSatConvex = true;
    btBoxShape box(btVector3(0.05f, 0.05f, 0.05f));
    box.setMargin(0.001f);
    box.initializePolyhedralFeatures();
    struct Points : btCollisionWorld::ContactResultCallback {
        std::vector<std::array<btScalar, 7>> all; // distance, point on B, normal on B
        btScalar addSingleResult(btManifoldPoint& cp, const btCollisionObjectWrapper*, int, int,
                                 const btCollisionObjectWrapper*, int, int) override {
            const btVector3 &p = cp.m_positionWorldOnB, &n = cp.m_normalWorldOnB;
            all.push_back({cp.getDistance(), p.x(), p.y(), p.z(), n.x(), n.y(), n.z()});
            return 0;
        }
    };
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int touching = 0;
    for (int piece = 0; piece < 10; ++piece) {
        const std::vector<Eigen::Vector3d> points = piece % 2 ? randomPiece(rng) : curvedShard(3 + piece, 3);
        const auto bullet = hullShape(bulletFeatures(points));
        const auto faces = hullShape(convexHullOf(points));
        for (int pose = 0; pose < 10; ++pose) {
            const Eigen::Vector3d dir = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
            Eigen::Vector3d far = points.front();
            for (const auto& p : points)
                if (p.dot(dir) > far.dot(dir)) far = p;
            btCollisionObject boxObject;
            boxObject.setCollisionShape(&box);
            boxObject.setWorldTransform(btTransform(btQuaternion(u(rng), u(rng), u(rng), 1.0).normalized(),
                                                    toBullet(Eigen::Vector3d(far + 0.03 * dir))));
            Points withBullet, withFaces;
            btCollisionObject hull;
            hull.setCollisionShape(bullet.get());
            world.contactPairTest(&hull, &boxObject, withBullet);
            hull.setCollisionShape(faces.get());
            world.contactPairTest(&hull, &boxObject, withFaces);
            EXPECT_EQ(withFaces.all, withBullet.all) << piece << " " << pose;
            touching += !withBullet.all.empty();
        }
    }
    EXPECT_GT(touching, 50); // the test compares contacts, not misses
}

// Edges whose directions have |x| of 0.5 ± 3e-7 in turn, across a slot boundary of the
// unique-edge lookup (slots of 4e-6 of |x|): all one direction to Bullet's initialize() (within
// 1e-6), and one here too, found across the boundary. (Hull points come from Bullet's grid, so
// such near-parallel edges are made here directly, as a fan of triangles.)
TEST(ConvexHullOfPoints, EdgesAcrossASlotBoundaryAreOneDirection) {
    btConvexPolyhedron fan;
    const btVector3 apex(0.3f, 2.0f, -0.4f);
    fan.m_vertices.push_back(apex);
    int below = 0, above = 0;
    for (int k = 0; k < 16; ++k) {
        const double x = 0.5 + (k % 2 ? 3e-7 : -3e-7);
        const btVector3 a(btScalar(0.1 * k), btScalar(-0.03 * k), 0.0f);
        const btVector3 b = a + btScalar(0.3 + 0.01 * k) * btVector3(btScalar(x), 0.0f, btScalar(std::sqrt(1.0 - x * x)));
        fan.m_vertices.push_back(a);
        fan.m_vertices.push_back(b);
        btFace face;
        face.m_indices.push_back(0);
        face.m_indices.push_back(fan.m_vertices.size() - 2);
        face.m_indices.push_back(fan.m_vertices.size() - 1);
        for (btScalar& p : face.m_plane) p = 0;
        fan.m_faces.push_back(face);
        const btVector3 edge = (a - b).normalized();
        (btFabs(edge.x()) < btScalar(0.5) ? below : above) += 1;
    }
    ASSERT_GT(below, 0);
    ASSERT_GT(above, 0);
    btConvexPolyhedron bullet = fan;
    bullet.initialize();
    findUniqueEdges(fan);
    ASSERT_EQ(fan.m_uniqueEdges.size(), bullet.m_uniqueEdges.size());
    for (int e = 0; e < fan.m_uniqueEdges.size(); ++e) EXPECT_EQ(fan.m_uniqueEdges[e], bullet.m_uniqueEdges[e]) << e;
    EXPECT_THROW(findUniqueEdges(fan), std::logic_error);
}

// Filled in place, the features are those returned; a polyhedron with anything in it is
// refused (the hull's features would be mixed with old ones).
TEST(ConvexHullOfPoints, FillsAnEmptyPolyhedronAsItReturnsOne) {
    std::vector<Eigen::Vector3d> points;
    for (const auto& p : kVaseShard) points.emplace_back(p[0], p[1], p[2]);
    btConvexPolyhedron filled;
    convexHullOf(points, filled);
    const btConvexPolyhedron returned = convexHullOf(points);
    test::expectSameFeaturesButTheInnerBox(filled, returned);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(filled.m_extents[k], returned.m_extents[k]) << k;
    EXPECT_THROW(convexHullOf(points, filled), std::logic_error);
}

// A shard of two boxes sharing a face: its hull shape's points are its features' vertices,
// and its features Bullet's over the corners each taken once and moved in by `shrink`, built
// in the shape itself (FragmentHull::buildFeatures) as convexHullOf returns them.
TEST(ConvexHullOfPoints, AShardHullIsBuiltInPlaceWithBulletsFeatures) {
    auto box = [](double x0, int firstId) {
        std::vector<Eigen::Vector3d> v;
        std::vector<int> ids;
        for (int k = 0; k < 8; ++k) {
            v.emplace_back(x0 + 0.1 * (k & 1), 0.07 * ((k >> 1) & 1) - 0.03, 0.05 * (k >> 2) - 0.02);
            ids.push_back((k & 1) ? firstId + 4 + (k >> 1) : firstId + (k >> 1)); // the x0 side shares ids
        }
        const std::vector<std::vector<int>> faces = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                                     {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}}; // outward
        return geometry::ConvexPolyhedron::create(v, faces, ids, "box");
    };
    // The second box's x0 side is the first one's far side: ids 4..7 both times.
    const std::vector<geometry::ConvexPolyhedron> primitives = {box(-0.1, 0), box(0.0, 4)};
    const double shrink = 1e-3;
    const auto hull = makeShardHull(primitives, 0.0005, shrink);
    std::vector<Eigen::Vector3d> corners;
    for (int id = 0; id < 12; ++id)
        for (const auto& p : primitives)
            for (size_t v = 0; v < p.vertices().size(); ++v)
                if (p.globalIds()[v] == id && int(corners.size()) == id) corners.push_back(p.vertices()[v] * (1.0 - shrink));
    ASSERT_EQ(corners.size(), 12u);
    const btConvexPolyhedron expected = convexHullOf(corners);
    test::expectSameFeaturesButTheInnerBox(*hull->getConvexPolyhedron(), expected);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(hull->getConvexPolyhedron()->m_extents[k], expected.m_extents[k]) << k;
    test::expectSameFeaturesButTheInnerBox(*hull->getConvexPolyhedron(), bulletFeatures(corners));
    ASSERT_EQ(hull->getNumPoints(), expected.m_vertices.size());
    for (int k = 0; k < hull->getNumPoints(); ++k) EXPECT_EQ(hull->getUnscaledPoints()[k], expected.m_vertices[k]);
    EXPECT_EQ(expected.m_vertices.size(), 8); // the shared face's corners lie on the hull's faces
    EXPECT_FLOAT_EQ(hull->getMargin(), 0.0005f);
}

TEST(ConvexHullOfPoints, PointsInOnePlaneAreRejected) {
    const std::vector<Eigen::Vector3d> flat = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.5, 0.5, 0}};
    EXPECT_THROW(convexHullOf(flat), InputError);
    EXPECT_THROW(convexHullOf({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}), InputError);
}

} // namespace
} // namespace shatter
