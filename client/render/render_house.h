/* House meshes for gale_render: an axis-aligned obstacle box as plastered walls with
 * windows and a pitched roof, as world-space triangles in the vertex layout of
 * shaders/house.vert. Pure CPU code: callable without a GL context. */
#ifndef GALE_RENDER_HOUSE_H
#define GALE_RENDER_HOUSE_H

enum {
    /* floats per vertex: position, normal, (u, v, wall height, half width), material
       (0 wall, 1 roof) */
    RENDER_HOUSE_FLOATS = 11,
    /* vertices (triangles, 14 of them) per box: two long walls, two end walls with their
       gables, two roof planes */
    RENDER_HOUSE_VERTS = 42,
};

/* Writes the RENDER_HOUSE_VERTS vertices of the box min_max = min x, y, z, max x, y, z
 * [m] (min <= max; the caller checks) at out, which has room for RENDER_HOUSE_VERTS *
 * RENDER_HOUSE_FLOATS floats, and returns the end of what it wrote. Four walls rise to
 * the eaves, the two end walls are closed by gable triangles, and two roof planes meet in a
 * ridge along the longer horizontal side at the box top. The roof rises 40 % of the
 * height, at most a 40 degree pitch. */
float *render_house_mesh(const float min_max[6], float *out);

#endif
