#version 300 es
// SH projection, pass 2 of 2: coefficient j (row j of a 1 x 9 target) is the sum of the
// partial sums that sh_project.glsl wrote for it (row j / 3 of layer j % 3).
precision highp float;
precision highp sampler2DArray;

uniform sampler2DArray uPartialSums; // uRows columns per slot, slot k's from k x uRows
uniform int uRows;

out vec4 fragColor;

void main()
{
    // Fragment (k, j): coefficient j of slot k.
    int j = int(gl_FragCoord.y);
    int first = int(gl_FragCoord.x) * uRows;
    vec3 sum = vec3(0.0);
    for (int i = 0; i < uRows; ++i)
        sum += texelFetch(uPartialSums, ivec3(first + i, j / 3, j % 3), 0).rgb;
    fragColor = vec4(sum, 1.0);
}
