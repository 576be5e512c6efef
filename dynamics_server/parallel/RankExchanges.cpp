#include "RankExchanges.hpp"

#include "MpiExchange.hpp"

#include <memory>

namespace bop::parallel {
namespace {

// An MpiExchange that keeps its rank grid alive (the grid goes first in the bases' order).
struct GridHolder {
    std::shared_ptr<const CartComm> grid;
};
class RankExchange : private GridHolder, public MpiExchange {
public:
    RankExchange(std::shared_ptr<const CartComm> grid, const core::Box& box, double reach)
        : GridHolder{std::move(grid)}, MpiExchange(*GridHolder::grid, box, reach) {}
};

}  // namespace

core::ExchangeMaker rankExchanges() {
    return [grid = std::shared_ptr<const CartComm>()](const core::Box& box,
                                                      double reach) mutable -> std::unique_ptr<core::Exchange> {
        if (!grid) grid = std::make_shared<const CartComm>(MPI_COMM_WORLD, box);  // collective
        return std::make_unique<RankExchange>(grid, box, reach);
    };
}

}  // namespace bop::parallel
