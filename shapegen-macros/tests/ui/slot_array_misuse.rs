shapegen::generator! {
    struct G;
    shapes: [cube];
    start: A;
    node A {
        slots { lots[4]: B = 0.5, one: B = 0.5 }
        |s| {
            child!(lots, s);
            child!(one[2], s);
        }
    }
    node B { |s| {} }
}
fn main() {}
