/* import_bench - lanray's OBJ reader against Assimp's OBJ importer on the
 * same file, side by side (make bench, tools/bench/bench-import).
 *
 *   import_bench FILE.obj [ROUNDS]
 *
 * Each round reads the file with obj_read (to a Mesh, as obj2tmd does) and
 * with aiImportFile (aiProcess_Triangulate, to Assimp's scene), alternating,
 * and the best time of each is printed with the ratio and the speed in MB/s.
 * The file is read once beforehand, so both find it in the page cache. */
#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>

#include "model/obj.h"
#include "base/timer.h"

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: import_bench FILE.obj [ROUNDS]\n");
        return 2;
    }
    char *end = NULL;
    long rounds = argc > 2 ? strtol(argv[2], &end, 10) : 3;
    if (rounds < 1 || rounds > 100 || (end && *end)) {
        fprintf(stderr, "import_bench: ROUNDS wants 1..100, got '%s'\n", argv[2]);
        return 2;
    }
    struct stat sb;
    if (stat(argv[1], &sb)) {
        perror(argv[1]);
        return 1;
    }
    double ours = 1e30, theirs = 1e30;
    unsigned long tris_ours = 0, tris_theirs = 0;
    for (int r = 0; r < rounds; r++) {
        Mesh m;
        Err err;
        double t0 = timer_now();
        if (obj_read(argv[1], NULL, &m, NULL, &err)) {
            fprintf(stderr, "import_bench: %s\n", err.msg);
            return 1;
        }
        double t1 = timer_now();
        tris_ours = m.tri_count;
        mesh_free(&m);
        const struct aiScene *sc = aiImportFile(argv[1], aiProcess_Triangulate);
        double t2 = timer_now();
        if (!sc) {
            fprintf(stderr, "import_bench: assimp: %s\n", aiGetErrorString());
            return 1;
        }
        tris_theirs = 0;
        for (unsigned i = 0; i < sc->mNumMeshes; i++)
            tris_theirs += sc->mMeshes[i]->mNumFaces;
        aiReleaseImport(sc);
        ours = t1 - t0 < ours ? t1 - t0 : ours;
        theirs = t2 - t1 < theirs ? t2 - t1 : theirs;
    }
    double mb = (double)sb.st_size / 1e6;
    printf("import: %.1f MB, %lu triangles: lanray %.3f s (%.1f MB/s), assimp %.3f s (%.1f MB/s, %lu faces), "
           "ratio %.2f\n",
           mb, tris_ours, ours, mb / ours, theirs, mb / theirs, tris_theirs, theirs / ours);
    return 0;
}
