//! Poses of the moving part and bounds on them (DOMAIN.md section 5).
