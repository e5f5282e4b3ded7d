/* meshes.h - closed test meshes with exactly shared vertices (indexed
 * construction), for the stability tests. */
#ifndef LANRAY_TEST_MESHES_H
#define LANRAY_TEST_MESHES_H

#include <stdlib.h>

#include "model/mesh.h"

/* Adds triangle (a, b, c) of an indexed vertex list. */
static inline void mesh_add_indexed(Mesh *m, const vec3 *v, int a, int b, int c)
{
    vec3 p[3] = {v[a], v[b], v[c]};
    if (!mesh_tri_is_degenerate(p))
        mesh_add(m, p, NULL, NULL, NULL, 0, NULL);
}

/* Icosphere of the given radius: an icosahedron subdivided `levels` times. */
static inline void mesh_icosphere(Mesh *m, real radius, int levels)
{
    const real t = (R(1) + sqrt(R(5))) / 2;
    int cap = 12 + 30 * (1 << (2 * levels)) * 2, nv = 12;
    vec3 *v = malloc((size_t)cap * sizeof *v);
    int (*f)[3] = malloc(sizeof(int[3]) * 20 * (size_t)(1 << (2 * levels)));
    const real base[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                              {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    const int faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                              {11, 10, 2}, {10, 7, 6}, {7, 1, 8},   {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                              {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (int i = 0; i < 12; i++)
        v[i] = v3_norm(v3(base[i][0], base[i][1], base[i][2]));
    int nf = 20;
    for (int i = 0; i < 20; i++)
        for (int k = 0; k < 3; k++)
            f[i][k] = faces[i][k];
    for (int l = 0; l < levels; l++) {
        int (*g)[3] = malloc(sizeof(int[3]) * (size_t)nf * 4);
        /* midpoints by a simple search of edges made so far: small meshes only */
        int (*edge)[3] = malloc(sizeof(int[3]) * (size_t)nf * 3);
        int ne = 0, ng = 0;
        for (int i = 0; i < nf; i++) {
            int mid[3];
            for (int k = 0; k < 3; k++) {
                int a = f[i][k], b = f[i][(k + 1) % 3], lo = a < b ? a : b, hi = a < b ? b : a, found = -1;
                for (int e = 0; e < ne && found < 0; e++)
                    if (edge[e][0] == lo && edge[e][1] == hi)
                        found = edge[e][2];
                if (found < 0) {
                    v[nv] = v3_norm(v3_scale(v3_add(v[lo], v[hi]), R(0.5)));
                    edge[ne][0] = lo, edge[ne][1] = hi, edge[ne][2] = nv, ne++;
                    found = nv++;
                }
                mid[k] = found;
            }
            int a = f[i][0], b = f[i][1], c = f[i][2];
            int tri[4][3] = {{a, mid[0], mid[2]}, {b, mid[1], mid[0]}, {c, mid[2], mid[1]}, {mid[0], mid[1], mid[2]}};
            for (int q = 0; q < 4; q++)
                for (int k = 0; k < 3; k++)
                    g[ng + q][k] = tri[q][k];
            ng += 4;
        }
        free(edge);
        free(f);
        f = g;
        nf = ng;
    }
    for (int i = 0; i < nv; i++)
        v[i] = v3_scale(v[i], radius);
    mesh_init(m, 0, NULL);
    for (int i = 0; i < nf; i++)
        mesh_add_indexed(m, v, f[i][0], f[i][1], f[i][2]);
    free(v);
    free(f);
}

/* Torus around the y axis: major radius big, tube radius small. */
static inline void mesh_torus(Mesh *m, real big, real small, int nu, int nv)
{
    vec3 *v = malloc((size_t)nu * nv * sizeof *v);
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++) {
            real a = R(2) * REAL_PI * (real)i / (real)nu, b = R(2) * REAL_PI * (real)j / (real)nv;
            real r = big + small * cos(b);
            v[i * nv + j] = v3(r * cos(a), small * sin(b), r * sin(a));
        }
    mesh_init(m, 0, NULL);
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++) {
            int i1 = (i + 1) % nu, j1 = (j + 1) % nv;
            mesh_add_indexed(m, v, i * nv + j, i1 * nv + j, i1 * nv + j1);
            mesh_add_indexed(m, v, i * nv + j, i1 * nv + j1, i * nv + j1);
        }
    free(v);
}

#endif
