//! Builds a finely refined L-block B-rep a few times (for profilers).
fn main() {
    let (l_block, _) = acsg::examples::l_block_and_box();
    let mut soup = acsg::topology::refine::triangle_soup(&l_block);
    while soup.polygons.len() < 100_000 {
        soup = acsg::topology::refine::refine_midpoints(&soup);
    }
    for _ in 0..3 {
        let part = acsg::model::Part::try_new(&soup, "fine").expect("valid");
        assert_eq!(part.faces().len(), 8);
    }
}
