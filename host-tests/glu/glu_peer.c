/*
 * The libGLU peer of `error_figures`: tessellates rational Bezier patches with GLU's NURBS
 * tessellator (GLU_NURBS_TESSELLATOR mode, GLU_PARAMETRIC_ERROR sampling, the caller's
 * matrices) and writes every triangle with its corners' patch parameters, so that the
 * triangles can be verified the same way as the kernel's.
 *
 * Parameters come from a second surface tessellated alongside the geometry: the texture
 * coordinates of a bilinear net, (i / p, j / q) at control point (i, j), which a Bezier
 * surface of any degree reproduces exactly as (u, v).
 *
 * Input (stdin, whitespace separated):
 *   viewport W H
 *   tolerance PIXELS
 *   modelview 16 numbers (column-major, as OpenGL)
 *   projection 16 numbers (column-major)
 *   patches N
 *   then per patch: P Q, then (P+1)(Q+1) lines "x y z w" (Euclidean point and weight),
 *   control point (i, j) at line i (Q+1) + j.
 *
 * Output (stdout): one line per triangle,
 *   "t PATCH u0 v0 x0 y0 z0 u1 v1 x1 y1 z1 u2 v2 x2 y2 z2",
 * then "ms BEST" : the best of fifteen runs of the tessellation alone (callbacks storing
 * triangles in memory, no output), in milliseconds.
 *
 * Build: cc -O2 -o glu_peer glu_peer.c -lGLU -lGL (see scripts/figures.sh).
 */
#include <GL/gl.h>
#include <GL/glu.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#ifndef CALLBACK
#define CALLBACK
#endif

typedef struct {
    float u, v, x, y, z;
} Corner;

typedef struct {
    int patch;
    Corner c[3];
} Triangle;

typedef struct {
    Triangle *tris;
    size_t count, capacity;
    int patch;
    GLenum mode;
    Corner strip[2];
    Corner first;
    int in_primitive;
    float pending_u, pending_v;
} Collector;

static void push(Collector *k, Corner a, Corner b, Corner c) {
    if (k->count == k->capacity) {
        k->capacity = k->capacity ? 2 * k->capacity : 4096;
        k->tris = realloc(k->tris, k->capacity * sizeof(Triangle));
        if (!k->tris) {
            fprintf(stderr, "glu_peer: out of memory\n");
            exit(1);
        }
    }
    Triangle *t = &k->tris[k->count++];
    t->patch = k->patch;
    t->c[0] = a;
    t->c[1] = b;
    t->c[2] = c;
}

static void CALLBACK on_begin(GLenum mode, void *data) {
    Collector *k = data;
    k->mode = mode;
    k->in_primitive = 0;
}

static void CALLBACK on_texcoord(GLfloat *st, void *data) {
    Collector *k = data;
    k->pending_u = st[0];
    k->pending_v = st[1];
}

static void CALLBACK on_vertex(GLfloat *p, void *data) {
    Collector *k = data;
    Corner c = {k->pending_u, k->pending_v, p[0], p[1], p[2]};
    int n = k->in_primitive++;
    switch (k->mode) {
    case GL_TRIANGLES:
        if (n % 3 == 2) push(k, k->strip[0], k->strip[1], c);
        else k->strip[n % 3] = c;
        break;
    case GL_TRIANGLE_STRIP:
    case GL_QUAD_STRIP:
        /* A quad strip's quads (2k, 2k+1, 2k+3, 2k+2) split as the triangle strip does. */
        if (n >= 2) {
            if (n % 2 == 0) push(k, k->strip[0], k->strip[1], c);
            else push(k, k->strip[1], k->strip[0], c);
        }
        k->strip[0] = k->strip[1];
        k->strip[1] = c;
        break;
    case GL_TRIANGLE_FAN:
    case GL_POLYGON:
        if (n == 0) k->first = c;
        else if (n >= 2) push(k, k->first, k->strip[1], c);
        k->strip[1] = c;
        break;
    case GL_QUADS:
        /* Quads a b c d as (a b c) and (a c d). */
        if (n % 4 == 0) k->first = c;
        else if (n % 4 == 1) k->strip[0] = c;
        else if (n % 4 == 2) k->strip[1] = c;
        else {
            push(k, k->first, k->strip[0], k->strip[1]);
            push(k, k->first, k->strip[1], c);
        }
        break;
    default:
        /* Points and lines carry no area. */
        break;
    }
}

static void CALLBACK on_end(void *data) {
    Collector *k = data;
    k->in_primitive = 0;
}

static void CALLBACK on_error(GLenum code) {
    fprintf(stderr, "glu_peer: GLU error %u: %s\n", code, (const char *)gluErrorString(code));
    exit(1);
}

static void expect(const char *word) {
    char buf[64];
    if (scanf("%63s", buf) != 1 || strcmp(buf, word) != 0) {
        fprintf(stderr, "glu_peer: expected '%s'\n", word);
        exit(1);
    }
}

typedef struct {
    int p, q;
    GLfloat *geometry; /* (p+1)(q+1) homogeneous points */
    GLfloat *params;   /* (p+1)(q+1) texture coordinates */
    GLfloat *uknots, *vknots;
} Patch;

static double now_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

static void tessellate(GLUnurbs *nurbs, Collector *k, Patch *patches, int n) {
    k->count = 0;
    for (int i = 0; i < n; i++) {
        Patch *pa = &patches[i];
        k->patch = i;
        gluBeginSurface(nurbs);
        gluNurbsSurface(nurbs, 2 * (pa->p + 1), pa->uknots, 2 * (pa->q + 1), pa->vknots,
                        2 * (pa->q + 1), 2, pa->params, pa->p + 1, pa->q + 1,
                        GL_MAP2_TEXTURE_COORD_2);
        gluNurbsSurface(nurbs, 2 * (pa->p + 1), pa->uknots, 2 * (pa->q + 1), pa->vknots,
                        4 * (pa->q + 1), 4, pa->geometry, pa->p + 1, pa->q + 1,
                        GL_MAP2_VERTEX_4);
        gluEndSurface(nurbs);
    }
}

int main(void) {
    GLint viewport[4] = {0, 0, 0, 0};
    GLfloat modelview[16], projection[16], tolerance;
    int n;
    expect("viewport");
    if (scanf("%d %d", &viewport[2], &viewport[3]) != 2) return 1;
    expect("tolerance");
    if (scanf("%f", &tolerance) != 1) return 1;
    expect("modelview");
    for (int i = 0; i < 16; i++)
        if (scanf("%f", &modelview[i]) != 1) return 1;
    expect("projection");
    for (int i = 0; i < 16; i++)
        if (scanf("%f", &projection[i]) != 1) return 1;
    expect("patches");
    if (scanf("%d", &n) != 1 || n <= 0) return 1;
    Patch *patches = calloc((size_t)n, sizeof(Patch));
    for (int i = 0; i < n; i++) {
        Patch *pa = &patches[i];
        if (scanf("%d %d", &pa->p, &pa->q) != 2) return 1;
        int count = (pa->p + 1) * (pa->q + 1);
        pa->geometry = malloc(sizeof(GLfloat) * 4 * count);
        pa->params = malloc(sizeof(GLfloat) * 2 * count);
        pa->uknots = malloc(sizeof(GLfloat) * 2 * (pa->p + 1));
        pa->vknots = malloc(sizeof(GLfloat) * 2 * (pa->q + 1));
        for (int a = 0; a <= pa->p; a++) {
            pa->uknots[a] = 0.0f;
            pa->uknots[pa->p + 1 + a] = 1.0f;
        }
        for (int b = 0; b <= pa->q; b++) {
            pa->vknots[b] = 0.0f;
            pa->vknots[pa->q + 1 + b] = 1.0f;
        }
        for (int a = 0; a <= pa->p; a++) {
            for (int b = 0; b <= pa->q; b++) {
                int at = a * (pa->q + 1) + b;
                float x, y, z, w;
                if (scanf("%f %f %f %f", &x, &y, &z, &w) != 4) return 1;
                pa->geometry[4 * at + 0] = x * w;
                pa->geometry[4 * at + 1] = y * w;
                pa->geometry[4 * at + 2] = z * w;
                pa->geometry[4 * at + 3] = w;
                pa->params[2 * at + 0] = (float)a / (float)pa->p;
                pa->params[2 * at + 1] = (float)b / (float)pa->q;
            }
        }
    }

    GLUnurbs *nurbs = gluNewNurbsRenderer();
    gluNurbsProperty(nurbs, GLU_NURBS_MODE, GLU_NURBS_TESSELLATOR);
    gluNurbsProperty(nurbs, GLU_SAMPLING_METHOD, GLU_PARAMETRIC_ERROR);
    gluNurbsProperty(nurbs, GLU_PARAMETRIC_TOLERANCE, tolerance);
    gluNurbsProperty(nurbs, GLU_DISPLAY_MODE, GLU_FILL);
    gluNurbsProperty(nurbs, GLU_CULLING, GL_TRUE);
    gluNurbsProperty(nurbs, GLU_AUTO_LOAD_MATRIX, GL_FALSE);
    gluLoadSamplingMatrices(nurbs, modelview, projection, viewport);
    Collector k;
    memset(&k, 0, sizeof k);
    gluNurbsCallbackData(nurbs, &k);
    gluNurbsCallback(nurbs, GLU_NURBS_BEGIN_DATA, (void (*)(void))on_begin);
    gluNurbsCallback(nurbs, GLU_NURBS_TEXTURE_COORD_DATA, (void (*)(void))on_texcoord);
    gluNurbsCallback(nurbs, GLU_NURBS_VERTEX_DATA, (void (*)(void))on_vertex);
    gluNurbsCallback(nurbs, GLU_NURBS_END_DATA, (void (*)(void))on_end);
    gluNurbsCallback(nurbs, GLU_NURBS_ERROR, (void (*)(void))on_error);

    double best = 1e300;
    for (int run = 0; run < 15; run++) {
        double start = now_ms();
        tessellate(nurbs, &k, patches, n);
        double ms = now_ms() - start;
        if (ms < best) best = ms;
    }
    for (size_t t = 0; t < k.count; t++) {
        Triangle *tr = &k.tris[t];
        printf("t %d", tr->patch);
        for (int c = 0; c < 3; c++)
            printf(" %.9g %.9g %.9g %.9g %.9g", tr->c[c].u, tr->c[c].v, tr->c[c].x, tr->c[c].y,
                   tr->c[c].z);
        printf("\n");
    }
    printf("ms %.4f\n", best);
    gluDeleteNurbsRenderer(nurbs);
    return 0;
}
