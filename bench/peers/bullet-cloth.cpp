// Bullet's classic soft body on the peers' scenes (bench/peers.sh; not part
// of drape's build). Reads the cloth's first frame as an OBJ in drape's
// y-up frame (vertices in drape's node order, drape's triangles), runs
// Bullet in its z-up frame (x, -z, y) with a fixed step, and writes each
// frame, back in drape's frame and order, as OBJ. Prints the wall seconds
// of the stepping alone (not the set-up nor the writing).
//
// usage: bullet-cloth IN.obj OUTDIR|- T FRAMES DT MASS_PER_NODE THICKNESS
//        FRICTION CUBE(0|1) [PITERATIONS]
// Build: g++ -O2 bullet-cloth.cpp $(pkg-config --cflags --libs bullet-float64)
#include <btBulletDynamicsCommon.h>
#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyInternals.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <set>
#include <string>
#include <utility>
#include <vector>

static btSoftBody *cloth;

// cluster self-collision: CL_SS|CL_SELF makes defaultCollisionHandler do
// nothing, so it is asked for here, once a step, before the soft bodies'
// constraints are solved
static void tick(btDynamicsWorld *, btScalar)
{
	btSoftColliders::CollideCL_SS self;
	self.ProcessSoftSoft(cloth, cloth);
}

static void write_obj(const std::string &path, const btSoftBody *sb,
		      const std::vector<int> &tri)
{
	FILE *f = std::fopen(path.c_str(), "w");
	if (!f) { std::perror(path.c_str()); std::exit(1); }
	for (int i = 0; i < sb->m_nodes.size(); i++) {
		const btVector3 &x = sb->m_nodes[i].m_x;
		std::fprintf(f, "v %.9g %.9g %.9g\n", (double)x.x(), (double)x.z(), (double)-x.y());
	}
	for (size_t t = 0; t < tri.size(); t += 3)
		std::fprintf(f, "f %d %d %d\n", tri[t] + 1, tri[t + 1] + 1, tri[t + 2] + 1);
	std::fclose(f);
}

int main(int argc, char **argv)
{
	if (argc < 10) {
		std::fprintf(stderr, "usage: %s IN.obj OUTDIR|- T FRAMES DT MASS THICKNESS FRICTION CUBE [PITERATIONS]\n", argv[0]);
		return 2;
	}
	const char *in = argv[1];
	std::string outdir = argv[2];
	double T = std::atof(argv[3]), dt = std::atof(argv[5]);
	int frames = std::atoi(argv[4]);
	double mass = std::atof(argv[6]), thick = std::atof(argv[7]), mu = std::atof(argv[8]);
	int cube = std::atoi(argv[9]), piter = argc > 10 ? std::atoi(argv[10]) : 4;

	std::vector<btVector3> x;
	std::vector<int> tri;
	FILE *f = std::fopen(in, "r");
	if (!f) { std::perror(in); return 1; }
	char line[512];
	while (std::fgets(line, sizeof line, f)) {
		double a, b, c;
		int i, j, k;
		if (std::sscanf(line, "v %lf %lf %lf", &a, &b, &c) == 3)
			x.push_back(btVector3(a, -c, b)); // drape's y up to z up
		else if (std::sscanf(line, "f %d %d %d", &i, &j, &k) == 3) {
			tri.push_back(i - 1); tri.push_back(j - 1); tri.push_back(k - 1);
		}
	}
	std::fclose(f);
	if (x.empty() || tri.empty()) { std::fprintf(stderr, "%s: no mesh\n", in); return 1; }

	btSoftBodyRigidBodyCollisionConfiguration config;
	btCollisionDispatcher dispatcher(&config);
	btDbvtBroadphase broadphase;
	btSequentialImpulseConstraintSolver solver;
	btSoftRigidDynamicsWorld world(&dispatcher, &broadphase, &solver, &config);
	const btVector3 g(0, 0, -9.80665);
	world.setGravity(g);
	btSoftBodyWorldInfo &wi = world.getWorldInfo();
	wi.m_gravity = g;
	wi.air_density = 0;
	wi.water_density = 0;
	wi.m_sparsesdf.Initialize();
	wi.m_sparsesdf.setDefaultVoxelsz(0.005); // default 0.25 m
	wi.m_sparsesdf.Reset();

	// the floor (a thick slab: the sparse SDF needs a convex shape) and the cube
	std::vector<btCollisionShape *> shapes;
	std::vector<btRigidBody *> bodies;
	auto add_box = [&](btVector3 half, btVector3 centre) {
		btBoxShape *s = new btBoxShape(half);
		s->setMargin(0.0005); // default 4 cm
		btTransform tr;
		tr.setIdentity();
		tr.setOrigin(centre);
		btRigidBody::btRigidBodyConstructionInfo ci(0, new btDefaultMotionState(tr), s);
		ci.m_friction = mu;
		btRigidBody *b = new btRigidBody(ci);
		world.addRigidBody(b);
		shapes.push_back(s);
		bodies.push_back(b);
	};
	add_box(btVector3(1, 1, 0.05), btVector3(0, 0, -0.05));
	if (cube)
		add_box(btVector3(0.05, 0.05, 0.05), btVector3(0.07, 0.05, 0.05));

	std::vector<btScalar> m(x.size(), mass);
	cloth = new btSoftBody(&wi, (int)x.size(), x.data(), m.data());
	std::set<std::pair<int, int>> edges;
	for (size_t t = 0; t < tri.size(); t += 3) {
		for (int e = 0; e < 3; e++) {
			int a = tri[t + e], b = tri[t + (e + 1) % 3];
			if (a > b) std::swap(a, b);
			if (edges.insert(std::make_pair(a, b)).second)
				cloth->appendLink(a, b);
		}
		cloth->appendFace(tri[t], tri[t + 1], tri[t + 2]);
	}
	cloth->m_materials[0]->m_kLST = 1;
	cloth->m_cfg.kDF = mu;
	cloth->m_cfg.kDP = 0;
	cloth->m_cfg.kDG = 0;
	cloth->m_cfg.kLF = 0;
	cloth->m_cfg.piterations = piter;
	cloth->m_cfg.collisions = btSoftBody::fCollision::SDF_RS | btSoftBody::fCollision::CL_SS |
				  btSoftBody::fCollision::CL_SELF;
	cloth->getCollisionShape()->setMargin(thick);
	cloth->generateClusters(0); // a cluster a triangle, for self-collision
	cloth->setActivationState(DISABLE_DEACTIVATION); // sleeps below 4 cm/s
	world.addSoftBody(cloth);
	world.setInternalTickCallback(tick, nullptr, false);

	int steps = (int)(T / dt + 0.5);
	bool out = outdir != "-";
	char name[64];
	if (out) {
		std::snprintf(name, sizeof name, "/frame-%04d.obj", 0);
		write_obj(outdir + name, cloth, tri);
	}
	double wall = 0;
	int frame = 0;
	for (int s = 1; s <= steps; s++) {
		auto t0 = std::chrono::steady_clock::now();
		world.stepSimulation(dt, 0, dt); // exactly one fixed step
		wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
		// frames at k * T / frames
		if (out && (long long)s * frames / steps > frame) {
			frame = (int)((long long)s * frames / steps);
			std::snprintf(name, sizeof name, "/frame-%04d.obj", frame);
			write_obj(outdir + name, cloth, tri);
		}
	}
	for (int i = 0; i < cloth->m_nodes.size(); i++)
		if (!std::isfinite((double)cloth->m_nodes[i].m_x.x())) {
			std::fprintf(stderr, "bullet: node %d not finite at the end\n", i);
			return 3;
		}
	std::printf("nodes %d triangles %zu steps %d dt %g\n", (int)x.size(), tri.size() / 3, steps, dt);
	std::printf("simulated %g s\nwall time %.3f s\n", T, wall);
	return 0;
}
