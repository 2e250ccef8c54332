shapegen::generator! {
    struct G;
    shapes: [cube];
    start: A;
    node A { slots { next: A = 1.5, other: A = -0.25 } |s| {} }
}
fn main() {}
