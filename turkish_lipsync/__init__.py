"""Turkish lip-sync: the core (no bpy) and the Blender layer."""
