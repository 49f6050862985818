/*
 * Times the MC33 library (D. Vega et al., "A Fast and Memory-Saving Marching
 * Cubes 33 implementation with the correct interior test", JCGT 8(3), 2019)
 * on a float32 .npy volume held in memory, for scripts/bench-peers.
 *
 * MC33's source is not part of this repository: scripts/bench-peers compiles
 * this file with -I pointing at a checkout of MC33_c_library (its
 * source/libMC33.c is included below as one translation unit).
 *
 * Usage: bench_peers_mc33 VOLUME.npy ISO
 * Loads the volume, prints {"ready":true,...}, then for every line read on
 * stdin runs one extraction (create_MC33 + calculate_isosurface; the mesh
 * stays in memory until the clock has stopped) and prints one JSON line
 * {"seconds":S,"triangles":T,"vertices":V}.
 */
#define GRD_ORTHOGONAL
#include "libMC33.c"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void) {
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return t.tv_sec + 1e-9 * t.tv_nsec;
}

/* Reads a little-endian float32, C-order, 3-D .npy file; returns the samples
 * (x fastest) and sets dims = {nx, ny, nz}, or prints why and returns NULL. */
static float *read_npy(const char *path, unsigned int dims[3]) {
	FILE *f = fopen(path, "rb");
	if (!f) {
		fprintf(stderr, "%s: cannot open\n", path);
		return NULL;
	}
	unsigned char pre[10];
	if (fread(pre, 1, 10, f) != 10 || memcmp(pre, "\x93NUMPY", 6) != 0) {
		fprintf(stderr, "%s: not a .npy file\n", path);
		fclose(f);
		return NULL;
	}
	size_t hlen;
	if (pre[6] == 1) {
		hlen = pre[8] | (pre[9] << 8);
	} else {
		unsigned char more[2];
		if (fread(more, 1, 2, f) != 2) {
			fclose(f);
			return NULL;
		}
		hlen = pre[8] | (pre[9] << 8) | ((size_t)more[0] << 16) | ((size_t)more[1] << 24);
	}
	char *header = calloc(hlen + 1, 1);
	if (!header || fread(header, 1, hlen, f) != hlen) {
		fprintf(stderr, "%s: short header\n", path);
		fclose(f);
		free(header);
		return NULL;
	}
	unsigned long shape[3];
	const char *s = strstr(header, "'shape'");
	if (!strstr(header, "'<f4'") || !strstr(header, "'fortran_order': False") || !s ||
	    sscanf(strchr(s, '('), "(%lu, %lu, %lu)", &shape[0], &shape[1], &shape[2]) != 3) {
		fprintf(stderr, "%s: need a C-order little-endian float32 3-D array, header %s\n", path,
			header);
		fclose(f);
		free(header);
		return NULL;
	}
	free(header);
	dims[0] = shape[2];
	dims[1] = shape[1];
	dims[2] = shape[0];
	size_t n = (size_t)shape[0] * shape[1] * shape[2];
	float *data = malloc(n * sizeof(float));
	if (!data || fread(data, sizeof(float), n, f) != n) {
		fprintf(stderr, "%s: short data\n", path);
		fclose(f);
		free(data);
		return NULL;
	}
	fclose(f);
	return data;
}

int main(int argc, char **argv) {
	if (argc != 3) {
		fprintf(stderr, "usage: %s VOLUME.npy ISO\n", argv[0]);
		return 2;
	}
	unsigned int dims[3];
	double t0 = now();
	float *data = read_npy(argv[1], dims);
	if (!data)
		return 1;
	float iso = (float)atof(argv[2]);
	_GRD *G = grid_from_data_pointer(dims[0], dims[1], dims[2], data);
	if (!G) {
		fprintf(stderr, "grid_from_data_pointer failed\n");
		return 1;
	}
	printf("{\"ready\":true,\"dims\":[%u,%u,%u],\"load_seconds\":%.6f}\n", dims[0], dims[1],
	       dims[2], now() - t0);
	fflush(stdout);
	char line[256];
	while (fgets(line, sizeof line, stdin)) {
		double start = now();
		MC33 *M = create_MC33(G);
		surface *S = M ? calculate_isosurface(M, iso) : NULL;
		double seconds = now() - start;
		if (!S) {
			fprintf(stderr, "MC33 failed (out of memory?)\n");
			return 1;
		}
		printf("{\"seconds\":%.6f,\"triangles\":%u,\"vertices\":%u}\n", seconds, S->nT, S->nV);
		fflush(stdout);
		free_surface_memory(S);
		free_MC33(M);
	}
	free_memory_grd(G);
	free(data);
	return 0;
}
