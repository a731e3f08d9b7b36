#version 300 es
// SH projection, pass 2 of 2: coefficient j (row j of a 1 x 9 target) is the sum of row j
// of the partial sums that sh_project.frag wrote.
precision highp float;
precision highp sampler2D;

uniform sampler2D uPartialSums; // uRows columns per slot, slot k's from k x uRows
uniform int uRows;

out vec4 fragColor;

void main()
{
    // Fragment (k, j): coefficient j of slot k.
    int j = int(gl_FragCoord.y);
    int first = int(gl_FragCoord.x) * uRows;
    vec3 sum = vec3(0.0);
    for (int i = 0; i < uRows; ++i)
        sum += texelFetch(uPartialSums, ivec2(first + i, j), 0).rgb;
    fragColor = vec4(sum, 1.0);
}
