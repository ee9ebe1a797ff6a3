//! The paper's start pose `P0` to both instrument modules' joints, both modes.
//!
//! `cargo run -p parasils-kin --example paper_start`

use parasils_kin::{Instrument, Pose, Side, TipTargets};

fn main() -> Result<(), parasils_kin::Error> {
    let p0 = Pose::<f64>::paper_start();
    let tips = TipTargets::<f64>::paper();
    println!("P0 = (15, 20, -500 mm, -15, 10, -60 deg)");
    for (side, tip) in [(Side::Left, tips.left), (Side::Right, tips.right)] {
        let module = Instrument::paper(side);
        let [a, b] = module.ik_solutions(&p0, &tip)?;
        println!(
            "{side:>5} tip ({:.4}, {:.4}, {:.4}) mm",
            tip.x, tip.y, tip.z
        );
        for (mode, q) in [("A", a), ("B", b)] {
            println!(
                "      mode {mode}: qs1 = {:9.4} deg, qs2 = {:9.4} deg, qs3 = {:8.4} mm, |cos qs2| = {:.4}",
                q.qs1.to_degrees(),
                q.qs2.to_degrees(),
                q.qs3,
                q.qs2.cos().abs()
            );
        }
    }
    Ok(())
}
