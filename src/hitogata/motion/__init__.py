"""Motion in and out: BVH files retargeted onto the 65-part skeleton, scenarios as BVH (docs/motion.md)."""
