// Flat workgroup index of a dispatch that the engine may have split into 2-D past the device's
// maxComputeWorkGroupCount[0] (65,535 on lavapipe). Groups past the wanted count must exit early.
uint flat_group_id() {
  return gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
}
