shapegen::generator! {
    struct G;
    shapes: [cube];
    start: A;
    node A { slots { next: Missing = 0.5 } |s| { child!(next, s); } }
}
fn main() {}
