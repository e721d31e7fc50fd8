//! Penetration of two parts at a pose, on their exact convex pieces.
