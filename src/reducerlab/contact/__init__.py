"""Contact and mesh stiffness of gear teeth."""
