shapegen::generator! {
    struct G;
    start: A;
    node A {
        slots { left: A = 0.5, right: A = 0.5, lots[4]: A = 0.1 }
        |s| {
            child!(left, s);
            if s.size.x > 1.0 {
                child!(left, s.translated([1.0, 0.0, 0.0].into()));
            } else {
                child!(right, s);
            }
            // Alternatives and distinct elements are fine.
            match s.size.y > 1.0 {
                true => child!(right, s),
                false => {}
            }
            child!(lots[0], s);
            child!(lots[1], s);
            child!(lots[1], s);
        }
    }
}
fn main() {}
