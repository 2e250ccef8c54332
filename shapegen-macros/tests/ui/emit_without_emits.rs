shapegen::generator! {
    struct G;
    shapes: [cube];
    start: A;
    node A {
        |s| { emit!(cube, s.instance()); }
    }
}
fn main() {}
