// Linear invocation index of a possibly 2D dispatch: rows of `row` invocations.
uint linear_invocation(uint row) {
  return gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * row;
}
