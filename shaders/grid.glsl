// The ground grid: anti-aliased minor lines every u_grid_spacing metres and major lines
// every five, both faded out before they would alias. Vertex shaders give the grid
// coordinate (grid_coord, linear in the world, so it interpolates exactly); fragment
// shaders draw the lines at it (grid_line).
uniform vec2 u_grid_offset;    // metres the ground has moved (added to world xz)
uniform float u_grid_spacing;  // metres between minor lines
uniform float u_grid_on;       // 0 or 1

vec2 grid_coord(vec2 world_xz) {
    return (world_xz + u_grid_offset) / u_grid_spacing;
}

float grid_line(vec2 coord) {
    vec2 fw = max(fwidth(coord), vec2(1e-6));
    vec2 per_pixel = 1.0 / fw;
    // Distances (in pixels) to the nearest minor and major line along each axis.
    vec2 minor_d = abs(coord - round(coord)) * per_pixel;
    vec2 major_coord = coord * 0.2;
    vec2 major_d = abs(major_coord - round(major_coord)) * (per_pixel * (1.0 / 0.3));
    float spread = max(fw.x, fw.y);
    float minor = (1.0 - min(min(minor_d.x, minor_d.y), 1.0)) * (1.0 - smoothstep(0.25, 0.6, spread));
    float major = (1.0 - min(min(major_d.x, major_d.y), 1.0)) * (1.0 - smoothstep(1.25, 3.0, spread));
    return u_grid_on * max(minor * 0.45, major * 0.8);
}
