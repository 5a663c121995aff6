/* Run-time shader loading for gale_render: shaders/<name>.vert and .frag are read from
 * the source tree (or $GALE_SHADER_DIR), each prefixed with "#version 330 core", a stage
 * define and shaders/common.glsl. Compile errors name the file and line; uniform locations
 * are looked up once here, at link time. */
#include "render_internal.h"

#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char *read_text(const char *path, gale_err *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        gale_errf(err, GALE_E_IO, "%s: cannot open shader", path);
        return NULL;
    }
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    if (n < 0 || n > (1 << 20)) {
        fclose(f);
        gale_errf(err, GALE_E_IO, "%s: unreadable or larger than 1 MiB", path);
        return NULL;
    }
    char *s = malloc((size_t)n + 1);
    if (!s) {
        fclose(f);
        gale_errf(err, GALE_E_NOMEM, "%s: out of memory", path);
        return NULL;
    }
    size_t got = fread(s, 1, (size_t)n, f);
    fclose(f);
    s[got] = '\0';
    return s;
}

static int count_lines(const char *s)
{
    int n = 0;
    for (; *s; s++) {
        n += *s == '\n';
    }
    return n;
}

static GLuint compile(GLenum stage, const char *dir, const char *file, const char *common,
                      gale_err *err)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, file);
    char *body = read_text(path, err);
    if (!body) {
        return 0;
    }
    const char *head = stage == GL_VERTEX_SHADER ? "#version 330 core\n#define GALE_VERT 1\n"
                                                 : "#version 330 core\n#define GALE_FRAG 1\n";
    /* "#line 1" makes the driver's line numbers count from the file's first line */
    const char *src[4] = { head, common, "\n#line 1\n", body };
    GLuint sh = glCreateShader(stage);
    glShaderSource(sh, 4, src, NULL);
    glCompileShader(sh);
    GLint ok = 0;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    free(body);
    if (!ok) {
        char log[600];
        glGetShaderInfoLog(sh, sizeof log, NULL, log);
        glDeleteShader(sh);
        gale_errf(err, GALE_E_PARSE, "%s (after common.glsl, %d lines): %s", path,
                  count_lines(common), log);
        return 0;
    }
    return sh;
}

/* Sampler uniforms and the texture unit each reads. */
static const struct {
    const char *name;
    int unit;
} shader_units[] = { { "u_skel", RU_SKEL },   { "u_node", RU_NODE }, { "u_list", RU_LIST },
                     { "u_trees", RU_TREES }, { "u_vw", RU_VW },     { "u_q", RU_Q },
                     { "u_leaf", RU_LEAF },   { "u_wind", RU_WIND }, { "u_path", RU_PATH },
                     { "u_imp", RU_IMP },     { "u_cut", RU_CUT },   { "u_cutn", RU_CUTN },
                     { "u_plates", RU_PLATE }, { "u_stumps", RU_STUMP },
                     { "u_imp_wood", RU_IMP_WOOD } };

/* Every uniform location of render_prog and its name in the shaders. */
#define PROG_U(f)                    \
    {                                \
#f, offsetof(render_prog, f) \
    }
static const struct {
    const char *name;
    size_t offset;
} shader_uniforms[] = {
    PROG_U(u_viewproj),   PROG_U(u_eye),         PROG_U(u_sun_dir),     PROG_U(u_sun_col),
    PROG_U(u_sky_zenith), PROG_U(u_sky_horizon), PROG_U(u_ground_col),  PROG_U(u_fog_dist),
    PROG_U(u_time),       PROG_U(u_wind_origin), PROG_U(u_wind_extent), PROG_U(u_wind_uniform),
    PROG_U(u_base),       PROG_U(u_nodes),       PROG_U(u_target),      PROG_U(u_qstride),
    PROG_U(u_ab),         PROG_U(u_bark),        PROG_U(u_nleaves),     PROG_U(u_aspect),
    PROG_U(u_crown),      PROG_U(u_leafcol),     PROG_U(u_shape),       PROG_U(u_inv_viewproj),
    PROG_U(u_wall),       PROG_U(u_roof),        PROG_U(u_window),      PROG_U(u_bsize),
    PROG_U(u_npath),      PROG_U(u_pdt),         PROG_U(u_ncont),       PROG_U(u_cont),
    PROG_U(u_aspects),    PROG_U(u_pass),        PROG_U(u_rain),        PROG_U(u_spray),
    PROG_U(u_storm),      PROG_U(u_rain_clear),  PROG_U(u_leaf_total),  PROG_U(u_sway),
    PROG_U(u_crown_z),    PROG_U(u_leaf_grow),
};
#undef PROG_U

static GLuint program_link(const char *dir, const char *name, gale_err *err)
{
    char path[1024], vf[128], ff[128];
    snprintf(path, sizeof path, "%s/common.glsl", dir);
    char *common = read_text(path, err);
    if (!common) {
        return 0;
    }
    snprintf(vf, sizeof vf, "%s.vert", name);
    snprintf(ff, sizeof ff, "%s.frag", name);
    GLuint vs = compile(GL_VERTEX_SHADER, dir, vf, common, err);
    GLuint fs = vs ? compile(GL_FRAGMENT_SHADER, dir, ff, common, err) : 0;
    free(common);
    if (!fs) {
        if (vs) {
            glDeleteShader(vs);
        }
        return 0;
    }
    GLuint p = glCreateProgram();
    glAttachShader(p, vs);
    glAttachShader(p, fs);
    glLinkProgram(p);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[600];
        glGetProgramInfoLog(p, sizeof log, NULL, log);
        glDeleteProgram(p);
        gale_errf(err, GALE_E_PARSE, "%s/%s: link failed: %s", dir, name, log);
        return 0;
    }
    return p;
}

int render_program_load(const char *dir, const char *name, render_prog *out, gale_err *err)
{
    memset(out, 0, sizeof *out);
    GLuint p = program_link(dir, name, err);
    if (!p) {
        return err && err->code ? err->code : GALE_E_STATE;
    }
    glUseProgram(p);
    for (size_t i = 0; i < sizeof shader_units / sizeof shader_units[0]; i++) {
        GLint loc = glGetUniformLocation(p, shader_units[i].name);
        if (loc >= 0) {
            glUniform1i(loc, shader_units[i].unit);
        }
    }
    glUseProgram(0);
    out->id = p;
    for (size_t i = 0; i < sizeof shader_uniforms / sizeof shader_uniforms[0]; i++) {
        GLint *loc = (GLint *)((char *)out + shader_uniforms[i].offset);
        *loc = glGetUniformLocation(p, shader_uniforms[i].name);
    }
    return 0;
}
