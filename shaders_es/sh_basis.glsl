// The real SH basis of bands 0..2 in lumar's order (gles_renderer/environment_map.h:
// (0,0) (1,-1) (1,0) (1,1) (2,-2) (2,-1) (2,0) (2,1) (2,2), band 1 ordered y, z, x).
// The normalisation constants, named once: sh_project.glsl's per-coefficient terms are built
// from them too.
const float kSh00 = 0.282095;  // 1 / (2 sqrt(pi))
const float kSh1 = 0.488603;   // sqrt(3 / (4 pi))
const float kSh2Mixed = 1.092548; // sqrt(15 / (4 pi)): xy, yz, xz
const float kSh20 = 0.315392;  // sqrt(5 / (16 pi)): 3 z^2 - 1
const float kSh22 = 0.546274;  // sqrt(15 / (16 pi)): x^2 - y^2

void shBasis(vec3 d, out float y[9])
{
    y[0] = kSh00;
    y[1] = kSh1 * d.y;
    y[2] = kSh1 * d.z;
    y[3] = kSh1 * d.x;
    y[4] = kSh2Mixed * d.x * d.y;
    y[5] = kSh2Mixed * d.y * d.z;
    y[6] = kSh20 * (3.0 * d.z * d.z - 1.0);
    y[7] = kSh2Mixed * d.x * d.z;
    y[8] = kSh22 * (d.x * d.x - d.y * d.y);
}
