/* driver.c: runs files through a fuzz target without libFuzzer: every
 * file of its seed corpus (tests/fuzz/FUZZ_CORPUS_DIR, or the files
 * given), each whole and cut in halves, so make check exercises the
 * target's code on them. */
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef FUZZ_CORPUS_DIR
#define FUZZ_CORPUS_DIR "corpus"
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int
run_file(const char *path)
{
	FILE *f = fopen(path, "rb");
	unsigned char *buf;
	long n;

	if (f == NULL || fseek(f, 0, SEEK_END) != 0 || (n = ftell(f)) < 0) {
		fprintf(stderr, "driver: %s: cannot read\n", path);
		if (f != NULL)
			fclose(f);
		return -1;
	}
	rewind(f);
	if ((buf = malloc((size_t)n + 1)) == NULL || fread(buf, 1, (size_t)n, f) != (size_t)n) {
		fprintf(stderr, "driver: %s: cannot read\n", path);
		free(buf);
		fclose(f);
		return -1;
	}
	fclose(f);
	LLVMFuzzerTestOneInput(buf, (size_t)n);
	LLVMFuzzerTestOneInput(buf, (size_t)n / 2);
	LLVMFuzzerTestOneInput(buf + n / 2, (size_t)(n - n / 2));
	free(buf);
	printf("ok %s (%ld bytes)\n", path, n);
	return 0;
}

int
main(int argc, char **argv)
{
	const char *corpus = TOP_SRCDIR "/tests/fuzz/" FUZZ_CORPUS_DIR;
	char path[4096];
	struct dirent *e;
	DIR *d;
	int i, bad = 0, files = 0;

	if (argc > 1) {
		for (i = 1; i < argc; i++)
			bad |= run_file(argv[i]) != 0;
		return bad;
	}
	if ((d = opendir(corpus)) == NULL) {
		fprintf(stderr, "driver: %s: cannot open\n", corpus);
		return 1;
	}
	while ((e = readdir(d)) != NULL) {
		if (e->d_name[0] == '.')
			continue;
		snprintf(path, sizeof path, "%s/%s", corpus, e->d_name);
		bad |= run_file(path) != 0;
		files++;
	}
	closedir(d);
	if (files == 0) {
		fprintf(stderr, "driver: %s: no seed files\n", corpus);
		return 1;
	}
	return bad;
}
