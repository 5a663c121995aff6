// Houses: the scene's obstacle boxes as plastered walls under a pitched roof. The mesh is
// built on the CPU in world coordinates (render.c house_mesh), so this only projects it.
layout(location = 0) in vec3 a_pos;   // world [m]
layout(location = 1) in vec3 a_nrm;   // outward unit normal
layout(location = 2) in vec4 a_attr;  // u along the face from its midline [m], v [m], wall height [m], half face width [m]
layout(location = 3) in float a_mat;  // 0 wall, 1 roof
out vec3 v_wpos;
out vec3 v_nrm;
out vec4 v_attr;
flat out float v_mat;
void main()
{
    v_wpos = a_pos;
    v_nrm = a_nrm;
    v_attr = a_attr;
    v_mat = a_mat;
    gl_Position = u_viewproj * vec4(a_pos, 1.0);
}
