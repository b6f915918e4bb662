/* fuzz_scene.c: scene files on arbitrary bytes, in two modes:
 *
 *   parse (the default): scene_parse_bytes, as drape reads a scene file;
 *   run (built with -DFUZZ_SCENE_RUN): a scene that parses, if it has at
 *	most FUZZ_MAX_NODES nodes and FUZZ_MAX_MESH_TRIANGLES obstacle
 *	triangles, built into a stepper and run FUZZ_STEPS steps.
 *
 * An input may carry the OBJ file of its [mesh] sections after a line
 * "%%obj": the target writes that part to fuzz.obj in a directory of its
 * own, in which the scene is read, and leaves alone an input whose [mesh]
 * names any other file (the fuzzer must not read /dev/stdin or a FIFO).
 *
 * libFuzzer's entry point; tests/fuzz/driver.c runs the seed corpus
 * (corpus-scene/: every shipped scene, and one with a mesh) through both
 * modes in make check. */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "forces.h"
#include "ini.h"
#include "scene.h"
#include "stepper.h"

#define FUZZ_MAX_NODES 4096
#define FUZZ_MAX_MESH_TRIANGLES 4096
#define FUZZ_STEPS 4

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char dir[64];		/* in /dev/shm when there is one: no disk */
static char scene_path[sizeof dir + 16], obj_path[sizeof dir + 16];

static void
cleanup(void)
{
	remove(obj_path);
	rmdir(dir);
}

static int
make_dir(void)
{
	static int made = -1;

	if (made < 0) {
		snprintf(dir, sizeof dir, "%s/drape-fuzz-scene-XXXXXX",
		    access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp");
		made = mkdtemp(dir) != NULL;
		if (made) {
			snprintf(scene_path, sizeof scene_path, "%s/fuzz.scene", dir);
			snprintf(obj_path, sizeof obj_path, "%s/fuzz.obj", dir);
			atexit(cleanup);
		}
	}
	return made;
}

/* -1 if a [mesh] file of the text is not fuzz.obj, else the number of
 * [mesh] files (0 too if the text does not split into lines and sections:
 * the parser then stops before any mesh). */
static int
our_meshes(const char *text)
{
	struct ini ini;
	struct drape_err err;
	size_t i;
	int n = 0;

	if (strstr(text, "mesh") == NULL || ini_parse(&ini, "fuzz.scene", text, &err) != 0)
		return 0;
	for (i = 0; i < ini.n && n >= 0; i++)
		if (ini.e[i].key != NULL && strcmp(ini.e[i].section, "mesh") == 0 &&
		    strcmp(ini.e[i].key, "file") == 0)
			n = strcmp(ini.e[i].value, "fuzz.obj") == 0 ? n + 1 : -1;
	ini_free(&ini);
	return n;
}

/* fuzz.obj holds obj, or is absent when obj is NULL; it is written only
 * when a [mesh] may read it, and removed only when it was written. */
static int
write_obj(const uint8_t *obj, size_t len)
{
	static int there;
	FILE *f;
	int ok;

	if (obj == NULL) {
		if (there && remove(obj_path) != 0)
			return 0;
		there = 0;
		return 1;
	}
	there = 1;
	if ((f = fopen(obj_path, "wb")) == NULL)
		return 0;
	ok = fwrite(obj, 1, len, f) == len;
	return fclose(f) == 0 && ok;
}

#ifdef FUZZ_SCENE_RUN
static void
run(const struct scene *sc)
{
	struct stepper *st;
	struct stepper_report r;
	struct drape_err err;
	struct step_failure f;
	struct energy e;
	char msg[600];
	size_t o, tris = 0;
	int k;

	for (o = 0; o < sc->nobstacles; o++)
		tris += sc->obstacles[o].mesh.ntri;
	if ((long)sc->nu * sc->nv > FUZZ_MAX_NODES || tris > FUZZ_MAX_MESH_TRIANGLES)
		return;
	if ((st = stepper_new(sc, &err)) == NULL)
		return;
	for (k = 0; k < FUZZ_STEPS && !stepper_done(st); k++)
		if (stepper_step(st, &f) != STEP_OK) {
			step_failure_format(&f, msg, sizeof msg);
			break;
		}
	stepper_energy(st, &e);
	stepper_report(st, &r);
	(void)stepper_hash(st);
	stepper_free(st);
}
#endif

int
LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	static const char mark[] = "\n%%obj\n";
	const uint8_t *obj = NULL;
	size_t len = size, objlen = 0, i;
	int meshes;
	struct scene sc;
	struct drape_err err;
	char *text;

	if (!make_dir())
		return 0;
	for (i = 0; i + sizeof mark - 1 <= size; i++)
		if (memcmp(data + i, mark, sizeof mark - 1) == 0) {
			len = i + 1;
			obj = data + i + sizeof mark - 1;
			objlen = size - (i + sizeof mark - 1);
			break;
		}
	if ((text = malloc(len + 1)) == NULL)
		return 0;
	memcpy(text, data, len);
	text[len] = '\0';
	meshes = strlen(text) == len ? our_meshes(text) : 0;
	free(text);
	if (meshes < 0 || !write_obj(meshes > 0 ? obj : NULL, objlen))
		return 0;
	if (scene_parse_bytes(&sc, scene_path, data, len, &err) != 0)
		return 0;
#ifdef FUZZ_SCENE_RUN
	run(&sc);
#endif
	scene_free(&sc);
	return 0;
}
