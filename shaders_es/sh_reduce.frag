#version 300 es
// SH projection, pass 2 of 2: coefficient j (row j of a 1 x 9 target) is the sum of row j
// of the partial sums that sh_project.frag wrote.
precision highp float;
precision highp sampler2D;

uniform sampler2D uPartialSums;

out vec4 fragColor;

void main()
{
    int j = int(gl_FragCoord.y);
    int columns = textureSize(uPartialSums, 0).x;
    vec3 sum = vec3(0.0);
    for (int i = 0; i < columns; ++i)
        sum += texelFetch(uPartialSums, ivec2(i, j), 0).rgb;
    fragColor = vec4(sum, 1.0);
}
