shapegen::generator! {
    struct G;
    start: A;
    node A {
        slots { fork[3]: A = 0.5 }
        |s| {
            child!(fork[2], s);
            child!(fork[3], s);
        }
    }
}
fn main() {}
